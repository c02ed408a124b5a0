// Volume helpers that need no file format: the value range and the histogram,
// axis alignment and the half-resolution preview.
// Readers live in volume_io.cpp, synthetic volumes in procedural.cpp.
#include "renderer/model/volume.h"

#include "renderer/errors.h"
#include "renderer/io/volume_io.h"   // kMaxVoxels

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>

namespace renderer {

void updateRange(Volume& volume) {
    // An empty or all-NaN volume gets {0, 0} so callers never see an inverted or infinite range.
    volume.range = volume.values.visit([](const auto& values) {
        bool any = false;
        ValueRange range;
        for (const auto stored : values) {
            const float v = float(stored);
            if (!std::isfinite(v)) continue;
            if (!any) {
                range = {v, v};
                any = true;
            } else {
                range.lo = std::min(range.lo, v);
                range.hi = std::max(range.hi, v);
            }
        }
        return any ? range : ValueRange{};
    });
}

Histogram computeHistogram(const Volume& volume, int bins) {
    if (bins < 1) throw RenderError("computeHistogram: bins is " + std::to_string(bins) + ", expected >= 1");
    Histogram h;
    h.range = volume.range;
    h.counts.assign(size_t(bins), 0);
    const double lo = h.range.lo, hi = h.range.hi;
    // A constant volume has zero width; every value then counts in bin 0 rather than dividing by zero.
    const double scale = hi > lo ? double(bins) / (hi - lo) : 0.0;
    volume.values.visit([&](const auto& values) {
        for (const auto stored : values) {
            const float v = float(stored);
            // Values outside the range (a stale range, NaN, Inf) are not counted: no bin covers them.
        if (!std::isfinite(v) || v < lo || v > hi) continue;
        // v == hi would land one past the end; it belongs to the last (closed) bin.
            const int bin = std::min(int((v - lo) * scale), bins - 1);
            ++h.counts[size_t(bin)];
        }
    });
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
    out.values = volume.values.visit([&](const auto& in) {   // in the file's type
        std::remove_cvref_t<decltype(in)> moved(in.size());
        for (int z = 0; z < volume.dims.z; ++z)
            for (int y = 0; y < volume.dims.y; ++y)
                for (int x = 0; x < volume.dims.x; ++x) {
                    const glm::ivec3 from{x, y, z};
                    glm::ivec3 at{0};
                    for (int axis = 0; axis < 3; ++axis)
                        at[map.world[size_t(axis)]] =
                            map.sign[size_t(axis)] > 0 ? from[axis] : start[axis] - from[axis];
                    moved[out.index(at.x, at.y, at.z)] = in[volume.index(x, y, z)];
                }
        return VoxelValues(std::move(moved));
    });
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
    if (isRotation(volume.directions)) return volume;
    glm::dmat3 flipped = volume.directions;
    flipped[0] = -flipped[0];
    if (isRotation(flipped)) return reordered(volume, AxisMap{.world = {0, 1, 2}, .sign = {-1, 1, 1}}, flipped);
    return resampledOntoWorldAxes(volume);
}

namespace {

// One index step along each of `volume`'s axes, in the world (columns).
glm::dmat3 indexStepsInWorld(const Volume& volume) {
    return volume.directions * glm::dmat3(glm::dvec3(volume.spacing.x, 0, 0), glm::dvec3(0, volume.spacing.y, 0),
                                          glm::dvec3(0, 0, volume.spacing.z));
}

} // namespace

Volume worldGrid(const Volume& volume) {
    const glm::dmat3 toWorld = indexStepsInWorld(volume);
    const double det = glm::determinant(toWorld);
    if (!(std::abs(det) > 1e-9 * volume.spacing.x * volume.spacing.y * volume.spacing.z))
        throw LoadError(volume.name, "directions", "the axes are parallel or not finite: no volume to resample");
    Volume out;
    out.name = volume.name;
    out.type = volume.type;
    out.resampled = true;
    const glm::dvec3 last(glm::max(volume.dims - 1, 0));
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 at(corner & 1 ? last.x : 0.0, corner & 2 ? last.y : 0.0, corner & 4 ? last.z : 0.0);
        lo = glm::min(lo, volume.origin + toWorld * at);
        hi = glm::max(hi, volume.origin + toWorld * at);
    }
    // Each world axis takes the step of the index axis most along it, as far as it goes along it: so
    // a CT tilted about x keeps its slice distance along z and its pixel size in x and y.
    for (int k = 0; k < 3; ++k) {
        double step = 0.0;
        for (int j = 0; j < 3; ++j) step = std::max(step, std::abs(toWorld[j][k]));
        out.spacing[k] = step;
        out.dims[k] = int(std::floor((hi[k] - lo[k]) / step + 1e-6)) + 1;
    }
    out.origin = lo;
    // At most 8 times the file's voxels (at least 1 M), and never more than a loader accepts.
    const size_t limit = std::min(kMaxVoxels, 8 * std::max<size_t>(volume.voxelCount(), 1 << 17));
    if (out.voxelCount() > limit)
        throw LoadError(volume.name, "directions",
                        "the axes are sheared so far that the world-aligned grid holding the volume would have " +
                            std::to_string(out.dims.x) + " x " + std::to_string(out.dims.y) + " x " +
                            std::to_string(out.dims.z) + " voxels, more than the " + std::to_string(limit) +
                            " allowed (8 times the file's)");
    return out;
}

Volume resampledOntoWorldAxes(const Volume& volume) {
    Volume out = worldGrid(volume);
    if (volume.values.empty()) {   // axes only (info's question): no voxels to resample
        out.dims = glm::ivec3(0);
        return out;
    }
    const glm::dmat3 fromWorld = glm::inverse(indexStepsInWorld(volume));
    const glm::dvec3 last(glm::max(volume.dims - 1, 0));
    // Trilinear in the file's index space; where the grid reaches past the scan, the data's minimum (air).
    const float outside = volume.range.lo;
    std::vector<float>& values = out.values.floats();   // trilinear mixes: floats whatever the file's type
    values.assign(out.voxelCount(), outside);
    tbb::parallel_for(0, out.dims.z, [&](int z) {
        for (int y = 0; y < out.dims.y; ++y)
            for (int x = 0; x < out.dims.x; ++x) {
                const glm::dvec3 f = fromWorld * (out.positionOf(x, y, z) - volume.origin);
                constexpr double kEdge = 1e-6;   // grid points on the scan's faces, up to rounding
                if (glm::any(glm::lessThan(f, glm::dvec3(-kEdge))) || glm::any(glm::greaterThan(f, last + kEdge)))
                    continue;
                const glm::dvec3 g = glm::clamp(f, glm::dvec3(0.0), last);
                const glm::ivec3 i0 = glm::min(glm::ivec3(glm::floor(g)), glm::max(volume.dims - 2, 0));
                const glm::dvec3 t = glm::min(g - glm::dvec3(i0), glm::dvec3(1.0));
                const glm::ivec3 i1 = glm::min(i0 + 1, volume.dims - 1);
                double sum = 0.0;
                for (int c = 0; c < 8; ++c) {
                    const glm::ivec3 at(c & 1 ? i1.x : i0.x, c & 2 ? i1.y : i0.y, c & 4 ? i1.z : i0.z);
                    const double w = (c & 1 ? t.x : 1.0 - t.x) * (c & 2 ? t.y : 1.0 - t.y) * (c & 4 ? t.z : 1.0 - t.z);
                    if (w != 0.0) sum += w * double(volume.at(at.x, at.y, at.z));   // 0 x NaN would be NaN
                }
                values[out.index(x, y, z)] = float(sum);
            }
    });
    updateRange(out);
    return out;
}

Volume halfResolution(const Volume& volume, Downsample how) {
    const glm::ivec3 step = glm::clamp(volume.dims, 1, 2);   // 1 on an axis of one voxel (or none)
    Volume coarse;
    coarse.name = volume.name;
    coarse.dims = (volume.dims + step - 1) / step;
    coarse.spacing = volume.spacing * glm::dvec3(step);
    coarse.origin = volume.origin + 0.5 * volume.spacing * glm::dvec3(step - 1);
    coarse.directions = volume.directions;
    coarse.type = volume.type;
    std::vector<float>& values = coarse.values.floats();   // a mean of integers is not one
    values.resize(coarse.voxelCount());
    for (int z = 0; z < coarse.dims.z; ++z)
        for (int y = 0; y < coarse.dims.y; ++y)
            for (int x = 0; x < coarse.dims.x; ++x) {
                double sum = 0.0;
                int n = 0;
                std::array<float, 8> finite{};
                for (int k = z * step.z; k < std::min((z + 1) * step.z, volume.dims.z); ++k)
                    for (int j = y * step.y; j < std::min((y + 1) * step.y, volume.dims.y); ++j)
                        for (int i = x * step.x; i < std::min((x + 1) * step.x, volume.dims.x); ++i)
                            if (const float v = volume.at(i, j, k); std::isfinite(v)) sum += v, finite[size_t(n++)] = v;
                float value = std::nanf("");
                if (n > 0 && how == Downsample::Mean) value = float(sum / n);
                if (n > 0 && how == Downsample::PickOne) { // a child chosen by a hash of the coarse index
                    uint64_t h = uint64_t(coarse.index(x, y, z)) + 0x9E3779B97F4A7C15ull;
                    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
                    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
                    value = finite[size_t((h ^ (h >> 31)) % uint64_t(n))];
                }
                values[coarse.index(x, y, z)] = value;
            }
    updateRange(coarse);
    return coarse;
}

double densityFor(const Volume& coarse, const Volume& fine, double density) {
    const auto sum = [](const glm::dvec3& v) { return v.x + v.y + v.z; };
    return density * sum(coarse.spacing) / sum(fine.spacing);
}

} // namespace renderer
