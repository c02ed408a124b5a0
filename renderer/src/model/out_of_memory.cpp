// The messages of allocations that fail (out_of_memory.h).
#include "renderer/out_of_memory.h"

#include <array>
#include <cstdio>

namespace renderer {

std::string formatBytes(uint64_t bytes) {
    if (bytes < 1024) return std::to_string(bytes) + " bytes";
    const std::array<const char*, 4> units{"KiB", "MiB", "GiB", "TiB"};
    double value = double(bytes) / 1024.0;
    size_t unit = 0;
    while (value >= 1024.0 && unit + 1 < units.size())
        value /= 1024.0, ++unit;
    char text[32];
    std::snprintf(text, sizeof text, value < 100.0 ? "%.1f %s" : "%.0f %s", value, units[unit]);
    return text;
}

std::string volumeSubject(const std::string& name) {
    return name.empty() ? std::string("the volume") : "volume '" + name + "'";
}

RenderError outOfMemory(const std::string& whose, const std::string& what, uint64_t bytes,
                        const std::string& where, Memory memory) {
    return RenderError(whose + ": out of " + (memory == Memory::Gpu ? "GPU memory" : "memory") +
                       " allocating the " + what + (bytes ? " (" + formatBytes(bytes) + ")" : std::string()) +
                       where);
}

} // namespace renderer
