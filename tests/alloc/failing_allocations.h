// Test-only: makes operator new of this test binary throw std::bad_alloc for large requests, so a test
// can run out of memory at one allocation of the code under test without using up the machine's.
#pragma once
#include <cstddef>

// While one lives, every request of more than `bytes` to operator new (on any thread) throws
// std::bad_alloc; smaller ones are served as usual. Destroy it to allocate normally again.
class FailingAllocations {
  public:
    explicit FailingAllocations(size_t bytes);
    ~FailingAllocations();
    FailingAllocations(const FailingAllocations&) = delete;
    FailingAllocations& operator=(const FailingAllocations&) = delete;
};
