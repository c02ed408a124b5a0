// Replaces operator new and delete in this test binary (failing_allocations.h): malloc and free, with a
// size above which new throws while a FailingAllocations lives. Aligned new and delete stay the library's.
#include "failing_allocations.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<size_t> g_failAbove{0}; // 0: nothing fails

void* allocate(size_t size) {
    const size_t limit = g_failAbove.load(std::memory_order_relaxed);
    if (limit != 0 && size > limit) return nullptr;
    return std::malloc(size ? size : 1);
}

} // namespace

FailingAllocations::FailingAllocations(size_t bytes) { g_failAbove = bytes; }
FailingAllocations::~FailingAllocations() { g_failAbove = 0; }

void* operator new(size_t size) {
    if (void* p = allocate(size)) return p;
    throw std::bad_alloc();
}
void* operator new[](size_t size) {
    if (void* p = allocate(size)) return p;
    throw std::bad_alloc();
}
void* operator new(size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void* operator new[](size_t size, const std::nothrow_t&) noexcept { return allocate(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
