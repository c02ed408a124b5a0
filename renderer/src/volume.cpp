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

Volume halfResolution(const Volume& volume) {
    const glm::ivec3 step = glm::clamp(volume.dims, 1, 2);   // 1 on an axis of one voxel (or none)
    Volume coarse;
    coarse.name = volume.name;
    coarse.dims = (volume.dims + step - 1) / step;
    coarse.spacing = volume.spacing * glm::dvec3(step);
    coarse.origin = volume.origin + 0.5 * volume.spacing * glm::dvec3(step - 1);
    coarse.directions = volume.directions;
    coarse.type = volume.type;
    coarse.values.resize(coarse.voxelCount());
    for (int z = 0; z < coarse.dims.z; ++z)
        for (int y = 0; y < coarse.dims.y; ++y)
            for (int x = 0; x < coarse.dims.x; ++x) {
                double sum = 0.0;
                int n = 0;
                for (int k = z * step.z; k < std::min((z + 1) * step.z, volume.dims.z); ++k)
                    for (int j = y * step.y; j < std::min((y + 1) * step.y, volume.dims.y); ++j)
                        for (int i = x * step.x; i < std::min((x + 1) * step.x, volume.dims.x); ++i)
                            if (const float v = volume.at(i, j, k); std::isfinite(v)) sum += v, ++n;
                coarse.values[coarse.index(x, y, z)] = n > 0 ? float(sum / n) : std::nanf("");
            }
    updateRange(coarse);
    return coarse;
}

double densityFor(const Volume& coarse, const Volume& fine, double density) {
    const auto sum = [](const glm::dvec3& v) { return v.x + v.y + v.z; };
    return density * sum(coarse.spacing) / sum(fine.spacing);
}

} // namespace renderer
