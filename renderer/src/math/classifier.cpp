// Adaptive filter classification (see classifier.h).
#include "renderer/math/classifier.h"

#include <algorithm>
#include <limits>

namespace renderer {

namespace {
// The GPU classifies and builds footprints in float: a decision taken here for it keeps 0.1 % of room.
constexpr double kFloatMargin = 1.001;
} // namespace

AdaptiveThresholds adaptiveThresholds(glm::dvec3 spacing, const ImagePlane& plane, const SplatSettings& s) {
    // c_max bounds the footprint's elongation over the image (000 sec. 3.2): 2 max (u0^2 + u1^2 + u2^2) / u2^2,
    // whose maximum is at the corner farthest from the principal point, 1 + tan^2(fovY/2) (1 + (W/H)^2)
    // for a centred perspective image (1.299 at 1920x1080, fov 30), 1 for parallel rays.
    double cornerSpread = 0.0;   // max (u0^2 + u1^2) / u2^2 over the image
    if (!plane.orthographic)
        for (const glm::dvec2 corner : {glm::dvec2(0, 0), glm::dvec2(plane.width, 0), glm::dvec2(0, plane.height),
                                        glm::dvec2(plane.width, plane.height)}) {
            const glm::dvec2 offsetPx = corner - plane.centrePx;
            cornerSpread = std::max(cornerSpread, glm::dot(offsetPx, offsetPx) / (plane.fPx * plane.fPx));
        }
    const double cMax = s.cMax > 0.0 ? s.cMax : 2.0 * (1.0 + cornerSpread);
    AdaptiveThresholds t;
    t.reconstructionAbovePx = 1.0 / s.cMin;
    t.lowPassBelowPx = 1.0 / cMax;
    const glm::dvec3 sigma = s.kernelScale * spacing;
    t.sigmaMin = std::min({sigma.x, sigma.y, sigma.z});
    t.sigmaMax = std::max({sigma.x, sigma.y, sigma.z});
    return t;
}

FilterMode classifyDepth(double u2, const ImagePlane& plane, const AdaptiveThresholds& t, FilterMode previous,
                         double hysteresis) {
    // At or behind the near plane a kernel is as magnified as it gets (and is culled when drawn).
    if (!plane.orthographic && !(u2 > plane.nearDepth)) return FilterMode::Reconstruction;
    const double pxPerUnit = plane.pxPerUnit(u2);
    double reconAbove = t.reconstructionAbovePx, lowPassBelow = t.lowPassBelowPx;
    if (hysteresis > 0.0 && previous != FilterMode::Adaptive) {   // enter by 1 + h, leave by 1 / (1 + h)
        const double band = 1.0 + hysteresis;
        reconAbove = previous == FilterMode::Reconstruction ? reconAbove / band : reconAbove * band;
        lowPassBelow = previous == FilterMode::LowPass ? lowPassBelow * band : lowPassBelow / band;
    }
    if (t.sigmaMin * pxPerUnit > reconAbove) return FilterMode::Reconstruction;
    if (t.sigmaMax * pxPerUnit < lowPassBelow) return FilterMode::LowPass;
    return FilterMode::Ewa;
}

std::optional<FilterMode> uniformAdaptiveFilter(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing,
                                                const ImagePlane& plane, const SplatSettings& s) {
    // Pixels per unit fall with depth.
    const glm::dvec2 depths = plane.depthRange(dims, origin, spacing);
    const double u2min = depths.x, u2max = depths.y;
    if (!plane.orthographic && !(u2min > plane.nearDepth)) return std::nullopt;
    const double pxMax = plane.pxPerUnit(u2min);
    const double pxMin = plane.pxPerUnit(u2max);
    const AdaptiveThresholds t = adaptiveThresholds(spacing, plane, s);
    // Each threshold as far as hysteresis can move it (classifyDepth), and 0.1 % for float rounding.
    const double band = (1.0 + std::max(s.hysteresis, 0.0)) * kFloatMargin;
    const bool neverReconstruction = t.sigmaMin * pxMax <= t.reconstructionAbovePx / band;
    const bool neverLowPass = t.sigmaMax * pxMin >= t.lowPassBelowPx * band;
    if (t.sigmaMin * pxMin > t.reconstructionAbovePx * band) return FilterMode::Reconstruction;
    if (neverReconstruction && t.sigmaMax * pxMax < t.lowPassBelowPx / band) return FilterMode::LowPass;
    if (neverReconstruction && neverLowPass) return FilterMode::Ewa;
    return std::nullopt;
}

bool footprintsHoldThePixel(FilterMode drawn, glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing,
                            const ImagePlane& plane, const SplatSettings& s) {
    if (drawn == FilterMode::LowPass || drawn == FilterMode::Ewa) return true;
    if (s.surfaceFlatten > 1.0) return false;
    const AdaptiveThresholds t = adaptiveThresholds(spacing, plane, s);
    // Pixels per unit are least at the farthest voxel (none is drawn where that lies behind the eye).
    const double farthest = plane.depthRange(dims, origin, spacing).y;
    const double pxMin = plane.orthographic ? plane.fPx : (farthest > 0.0 ? plane.fPx / farthest : 0.0);
    if (t.sigmaMin * pxMin >= kFloatMargin) return true;
    return drawn == FilterMode::Adaptive &&
           t.reconstructionAbovePx >= (1.0 + std::max(s.hysteresis, 0.0)) * kFloatMargin;
}

FilterDepths filterDepths(const AdaptiveThresholds& t, const ImagePlane& plane) {
    const double inf = std::numeric_limits<double>::infinity();
    if (plane.orthographic) {   // pixels per unit do not change with depth: one filter for the view
        if (t.sigmaMin * plane.fPx > t.reconstructionAbovePx) return {inf, inf};
        if (t.sigmaMax * plane.fPx < t.lowPassBelowPx) return {0.0, 0.0};
        return {0.0, inf};
    }
    return {std::max(t.sigmaMin * plane.fPx / t.reconstructionAbovePx, plane.nearDepth),
            t.sigmaMax * plane.fPx / t.lowPassBelowPx};
}

PatchGrid patchGrid(glm::ivec3 dims, int axis, int patchSize) {
    PatchGrid g;
    g.axis = axis;
    g.size = std::max(patchSize, 1);
    g.columns = (dims[(axis + 1) % 3] + g.size - 1) / g.size;
    g.rows = (dims[(axis + 2) % 3] + g.size - 1) / g.size;
    g.slices = dims[axis];
    return g;
}

FilterMode classifyPatch(const SplatScene& scene, const ImagePlane& plane, const AdaptiveThresholds& t,
                         int patchSize, int axis, uint32_t voxel, FilterMode previous, double hysteresis) {
    const glm::ivec3 d = scene.dims;
    const glm::ivec3 v(int(voxel % uint32_t(d.x)), int((voxel / uint32_t(d.x)) % uint32_t(d.y)),
                       int(voxel / (uint32_t(d.x) * uint32_t(d.y))));
    const int p = std::max(patchSize, 1);
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;   // the slice's two in-plane axes
    const int a0 = v[a] / p * p, b0 = v[b] / p * p;
    const int a1 = std::min(a0 + p - 1, d[a] - 1), b1 = std::min(b0 + p - 1, d[b] - 1);
    FilterMode mode = FilterMode::Ewa;
    for (int corner = 0; corner < 4; ++corner) {
        glm::ivec3 c = v;
        c[a] = (corner & 1) ? a1 : a0;
        c[b] = (corner & 2) ? b1 : b0;
        const double u2 = plane.toCamera(scene.origin + scene.spacing * glm::dvec3(c)).z;
        const FilterMode m = classifyDepth(u2, plane, t, previous, hysteresis);
        if (corner == 0) mode = m;
        else if (m != mode) return FilterMode::Ewa;   // corners disagree: the full filter
    }
    return mode;
}

} // namespace renderer
