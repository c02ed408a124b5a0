// How an allocation that fails is reported: one RenderError naming whose it was, what was being
// allocated and how large, so neither the command line nor the editor shows a bare std::bad_alloc.
#pragma once
#include "renderer/errors.h"

#include <cstdint>
#include <new>
#include <string>

namespace renderer {

// "512 bytes", "12.0 KiB", "310 MiB", "1.2 GiB": one decimal below 100 of a unit.
std::string formatBytes(uint64_t bytes);

enum class Memory { Host, Gpu };

// "<whose>: out of [GPU ]memory allocating the <what> (<size>)<where>" (no size where `bytes` is 0:
// not known), e.g.
// "volume 'bonsai': out of GPU memory allocating the tile lists (1.2 GiB) at 1920x1080".
RenderError outOfMemory(const std::string& whose, const std::string& what, uint64_t bytes,
                        const std::string& where = "", Memory memory = Memory::Host);

// "volume 'bonsai'" (or "the volume" when the name is empty): whose memory it is in the messages above.
std::string volumeSubject(const std::string& name);

// Runs `work()`; a std::bad_alloc from it becomes outOfMemory(whose, what, bytes, where).
template <class Work>
decltype(auto) namingAllocation(const std::string& whose, const std::string& what, uint64_t bytes,
                                const std::string& where, Work&& work) {
    try {
        return work();
    } catch (const std::bad_alloc&) {
        throw outOfMemory(whose, what, bytes, where);
    }
}

} // namespace renderer
