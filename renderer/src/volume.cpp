// Volume helpers that need no file format: type names and sizes, the value range and the histogram,
// axis alignment and the half-resolution preview.
// Readers live in volume_io.cpp, synthetic volumes in procedural.cpp.
#include "renderer/volume.h"

#include "renderer/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
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

namespace {

// For each index axis, the world axis it runs along and its sign: nullopt where the axes are oblique.
struct AxisMap {
    std::array<int, 3> world{};
    std::array<int, 3> sign{};
};

std::optional<AxisMap> signedPermutation(const glm::dmat3& directions) {
    constexpr double kTolerance = 1e-6;
    AxisMap map;
    std::array<bool, 3> taken{};
    for (int axis = 0; axis < 3; ++axis) {
        int along = -1;
        for (int row = 0; row < 3; ++row) {
            const double c = std::abs(directions[axis][row]);
            if (!std::isfinite(c)) return std::nullopt;
            if (std::abs(c - 1.0) < kTolerance && along < 0) along = row;
            else if (c > kTolerance) return std::nullopt;
        }
        if (along < 0 || taken[size_t(along)]) return std::nullopt;
        taken[size_t(along)] = true;
        map.world[size_t(axis)] = along;
        map.sign[size_t(axis)] = directions[axis][along] > 0.0 ? 1 : -1;
    }
    return map;
}

// The voxels reordered so that index axis a runs along new axis map.world[a], reversed where map.sign[a]
// is -1; `directions` become the new axes' (dims, spacing and origin follow, so every voxel keeps its
// place in the world).
Volume reordered(const Volume& volume, const AxisMap& map, const glm::dmat3& directions) {
    Volume out;
    out.name = volume.name;
    out.type = volume.type;
    out.range = volume.range;
    out.directions = directions;
    out.origin = volume.origin;   // the old voxel at the new (0,0,0): the far end of each reversed axis
    glm::ivec3 start{0};
    for (int axis = 0; axis < 3; ++axis) {
        const int to = map.world[size_t(axis)];
        out.dims[to] = volume.dims[axis];
        out.spacing[to] = volume.spacing[axis];
        if (map.sign[size_t(axis)] < 0) {
            start[axis] = volume.dims[axis] - 1;
            out.origin += volume.directions[axis] * volume.spacing[axis] * double(volume.dims[axis] - 1);
        }
    }
    out.values.resize(volume.values.size());
    for (int z = 0; z < volume.dims.z; ++z)
        for (int y = 0; y < volume.dims.y; ++y)
            for (int x = 0; x < volume.dims.x; ++x) {
                const glm::ivec3 from{x, y, z};
                glm::ivec3 at{0};
                for (int axis = 0; axis < 3; ++axis)
                    at[map.world[size_t(axis)]] =
                        map.sign[size_t(axis)] > 0 ? from[axis] : start[axis] - from[axis];
                out.values[out.index(at.x, at.y, at.z)] = volume.values[volume.index(x, y, z)];
            }
    return out;
}

// The orthonormal axes nearest `directions` (the orthogonal factor of its polar decomposition), where
// they are within kHeaderRounding of orthonormal; nullopt where they are further (sheared) or not finite.
// Headers print direction cosines to a few digits: three digits leave the dot products of axes meant to
// be orthonormal off by up to 1.7e-3 (0.11 degrees), four by up to 1.7e-4.
std::optional<glm::dmat3> nearestOrthonormal(const glm::dmat3& directions) {
    constexpr double kHeaderRounding = 2e-3;
    const glm::dmat3 gram = glm::transpose(directions) * directions;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (!(std::abs(gram[i][j] - (i == j ? 1.0 : 0.0)) < kHeaderRounding)) return std::nullopt;
    // Newton's iteration for the polar factor converges quadratically this close: 2e-3 is under 1e-16
    // after three steps.
    glm::dmat3 q = directions;
    for (int step = 0; step < 5; ++step) q = 0.5 * (q + glm::transpose(glm::inverse(q)));
    return q;
}

} // namespace

bool isRotation(const glm::dmat3& m) {
    constexpr double kTolerance = 1e-6;
    const glm::dmat3 gram = glm::transpose(m) * m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (!(std::abs(gram[i][j] - (i == j ? 1.0 : 0.0)) < kTolerance)) return false;   // NaN fails too
    return glm::determinant(m) > 0.0;
}

bool axesAlignable(const glm::dmat3& directions) { return signedPermutation(directions).has_value(); }

Volume alignedToWorldAxes(Volume volume) {
    if (volume.directions == glm::dmat3(1.0)) return volume;
    if (const std::optional<glm::dmat3> q = nearestOrthonormal(volume.directions)) volume.directions = *q;
    if (const std::optional<AxisMap> map = signedPermutation(volume.directions))
        return reordered(volume, *map, glm::dmat3(1.0));
    glm::dmat3 flipped = volume.directions;
    flipped[0] = -flipped[0];
    if (!isRotation(flipped)) return volume;   // a rotation already, or sheared
    return reordered(volume, AxisMap{.world = {0, 1, 2}, .sign = {-1, 1, 1}}, flipped);
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
