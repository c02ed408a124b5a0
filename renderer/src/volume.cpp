// Volume helpers that need no file format: type names and sizes, the value range and the histogram.
// Readers live in volume_io.cpp, synthetic volumes in procedural.cpp.
#include "renderer/volume.h"

#include "renderer/errors.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace renderer {

const char* voxelTypeName(VoxelType t) {
    switch (t) {
    case VoxelType::U8: return "uint8";
    case VoxelType::U16: return "uint16";
    case VoxelType::I16: return "int16";
    case VoxelType::F32: return "float32";
    }
    return "unknown";
}

size_t voxelTypeBytes(VoxelType t) {
    switch (t) {
    case VoxelType::U8: return 1;
    case VoxelType::U16: return 2;
    case VoxelType::I16: return 2;
    case VoxelType::F32: return 4;
    }
    return 0;
}

void updateRange(Volume& volume) {
    bool any = false;
    ValueRange range;
    for (float v : volume.values) {
        if (!std::isfinite(v)) continue;
        if (!any) {
            range = {v, v};
            any = true;
        } else {
            range.lo = std::min(range.lo, v);
            range.hi = std::max(range.hi, v);
        }
    }
    // An empty or all-NaN volume gets {0, 0} so callers never see an inverted or infinite range.
    volume.range = any ? range : ValueRange{};
}

Histogram computeHistogram(const Volume& volume, int bins) {
    if (bins < 1) throw RenderError("computeHistogram: bins is " + std::to_string(bins) + ", expected >= 1");
    Histogram h;
    h.range = volume.range;
    h.counts.assign(size_t(bins), 0);
    const double lo = h.range.lo, hi = h.range.hi;
    // A constant volume has zero width; every value then counts in bin 0 rather than dividing by zero.
    const double scale = hi > lo ? double(bins) / (hi - lo) : 0.0;
    for (float v : volume.values) {
        // Values outside the range (a stale range, NaN, Inf) are not counted: no bin covers them.
        if (!std::isfinite(v) || v < lo || v > hi) continue;
        // v == hi would land one past the end; it belongs to the last (closed) bin.
        const int bin = std::min(int((v - lo) * scale), bins - 1);
        ++h.counts[size_t(bin)];
    }
    return h;
}

} // namespace renderer
