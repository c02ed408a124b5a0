// Which kernels a post-classified frame can skip (see post_reach.h).
#include "renderer/oracle/post_reach.h"

#include <algorithm>
#include <cmath>

namespace renderer {

namespace {

constexpr int kBrick = 2;   // voxels a brick side: min and max per brick, then grown across bricks

// Along `axis`, each brick's min (max) becomes the min (max) of the bricks within `radius` of it.
void growAlong(std::vector<uint16_t>& lo, std::vector<uint16_t>& hi, glm::ivec3 n, int axis, int radius) {
    if (radius <= 0) return;
    const std::vector<uint16_t> lo0 = lo, hi0 = hi;
    const glm::ivec3 step(1, n.x, n.x * n.y);
    for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
            for (int x = 0; x < n.x; ++x) {
                const glm::ivec3 b(x, y, z);
                const size_t at = size_t(x) + size_t(n.x) * (size_t(y) + size_t(n.y) * size_t(z));
                const int from = std::max(0, b[axis] - radius), to = std::min(n[axis] - 1, b[axis] + radius);
                for (int i = from; i <= to; ++i) {
                    const size_t other = at + size_t(ptrdiff_t(i - b[axis]) * step[axis]);
                    lo[at] = std::min(lo[at], lo0[other]);
                    hi[at] = std::max(hi[at], hi0[other]);
                }
            }
}

} // namespace

double postReach(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings, double slabUnits) {
    const glm::dvec3 s = scene.spacing;
    const double sigma = settings.kernelScale * std::max({s.x, s.y, s.z});
    const double farthest = glm::length(plane.toCamera(scene.centre)) + scene.radius + 3.0 * sigma;
    const double pixel = plane.orthographic ? 1.0 / plane.fPx : farthest / plane.fPx;
    // Across the ray the footprint (kernel and low-pass) reaches c sqrt(sigma^2 + p^2); along it the slabs a
    // kernel reaches lie within c sqrt(2) sigma of its centre (the conditional mean's spread and deviation,
    // slab_setup.cpp), plus a slab: together c sqrt(3 sigma^2 + p^2) + slab, with 10 % for the rays' angle.
    const double one = 1.1 * settings.cutoffSigmas * std::sqrt(3.0 * sigma * sigma + pixel * pixel) + slabUnits;
    return 2.0 * one + slabUnits;
}

std::vector<uint8_t> kernelsNearVisible(const SplatScene& scene, double reach) {
    const glm::ivec3 d = scene.dims, n = (d + kBrick - 1) / kBrick;
    const size_t bricks = size_t(n.x) * size_t(n.y) * size_t(n.z);
    std::vector<uint16_t> lo(bricks, UINT16_MAX), hi(bricks, 0);
    const auto brickOf = [&](int x, int y, int z) {
        return size_t(x / kBrick) + size_t(n.x) * (size_t(y / kBrick) + size_t(n.y) * size_t(z / kBrick));
    };
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x) {
                const uint16_t c = scene.classes[size_t(x) + size_t(d.x) * (size_t(y) + size_t(d.y) * size_t(z))];
                const size_t b = brickOf(x, y, z);
                lo[b] = std::min(lo[b], c), hi[b] = std::max(hi[b], c);
            }
    // A voxel anywhere in a brick reaches bricks up to ceil(reach / (brick side)) + 1 away along each axis.
    for (int axis = 0; axis < 3; ++axis)
        growAlong(lo, hi, n, axis, int(std::ceil(reach / (scene.spacing[axis] * kBrick))) + 1);
    // Classes with opacity, counted up to each class: "any visible in [a, b]" in two reads.
    const Lut& lut = scene.lut;
    std::vector<uint32_t> visibleBefore(lut.size() + 1, 0);
    for (size_t c = 0; c < lut.size(); ++c) visibleBefore[c + 1] = visibleBefore[c] + (lut[c].a > 0.0f);
    std::vector<uint8_t> brickNeeded(bricks);
    for (size_t b = 0; b < bricks; ++b) {
        // One class either side: a mean rounded past the range reads its neighbour (lutAt interpolates).
        const size_t a = lo[b] > 0 ? lo[b] - 1u : 0u, z = std::min<size_t>(size_t(hi[b]) + 1u, lut.size() - 1);
        brickNeeded[b] = lo[b] <= hi[b] && visibleBefore[z + 1] > visibleBefore[a];
    }
    std::vector<uint8_t> needed(scene.classes.size());
    for (int z = 0; z < d.z; ++z)
        for (int y = 0; y < d.y; ++y)
            for (int x = 0; x < d.x; ++x)
                needed[size_t(x) + size_t(d.x) * (size_t(y) + size_t(d.y) * size_t(z))] = brickNeeded[brickOf(x, y, z)];
    return needed;
}

} // namespace renderer
