// The ray a pixel sees, marched through the classified grid (see probe.h).
#include "renderer/oracle/probe.h"

#include "renderer/oracle/reference_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace renderer {

std::optional<PixelProbe> probePixel(const SplatScene& scene, const SplatSettings& settings, const ImagePlane& plane,
                                     glm::dvec2 pixel, double alphaAt) {
    if (scene.classes.empty() || !(plane.fPx > 0.0)) return std::nullopt;
    // 1. The ray in object space: camera-space start and direction (project() inverted), then W^-1.
    const glm::dvec2 xy = (pixel - plane.centrePx) / plane.fPx;
    const glm::dvec3 startCamera = plane.orthographic ? glm::dvec3(xy, 0.0) : glm::dvec3(0.0);
    const glm::dvec3 dirCamera = glm::normalize(plane.orthographic ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(xy, 1.0));
    const glm::dmat3 objectFromView = glm::inverse(plane.viewFromObject);
    const glm::dvec3 start = objectFromView * (startCamera - plane.translation), dir = objectFromView * dirCamera;

    // 2. Where it crosses the grid's box (voxel centres grown by half a voxel), by slabs.
    const glm::dvec3 lo = scene.origin - 0.5 * scene.spacing;
    const glm::dvec3 hi = scene.origin + (glm::dvec3(scene.dims) - 0.5) * scene.spacing;
    double enter = 0.0, leave = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (std::abs(dir[a]) < 1e-300) {
            if (start[a] < lo[a] || start[a] > hi[a]) return std::nullopt;
            continue;
        }
        double t0 = (lo[a] - start[a]) / dir[a], t1 = (hi[a] - start[a]) / dir[a];
        if (t0 > t1) std::swap(t0, t1);
        enter = std::max(enter, t0);
        leave = std::min(leave, t1);
    }
    if (!(enter < leave)) return std::nullopt;

    // 3. Front to back, half a voxel a step: alpha += (1 - alpha) (1 - exp(-g h)).
    const double step = 0.5 * std::min({scene.spacing.x, scene.spacing.y, scene.spacing.z});
    double alpha = 0.0;
    for (double t = enter + 0.5 * step; t < leave; t += step) {
        const glm::dvec3 p = start + t * dir;
        const glm::ivec3 v = glm::clamp(glm::ivec3(glm::round((p - scene.origin) / scene.spacing)), glm::ivec3(0),
                                        scene.dims - 1);
        const size_t index = (size_t(v.z) * size_t(scene.dims.y) + size_t(v.y)) * size_t(scene.dims.x) + size_t(v.x);
        alpha += (1.0 - alpha) * (1.0 - std::exp(-voxelExtinction(scene, settings, uint32_t(index)) * step));
        if (alpha >= alphaAt) return PixelProbe{v, alpha, plane.toCamera(scene.positionOf(uint32_t(index))).z};
    }
    return std::nullopt;
}

} // namespace renderer
