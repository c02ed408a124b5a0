// The near layer's kernels and a pixel's sums (see near_layer.h).
#include "renderer/oracle/near_layer.h"

#include "renderer/math/ewa.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/ray_kernel.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/oracle/sheet_compositing.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace renderer {

namespace {
constexpr double kFilterReachPx = 4.0; // the ground truth's V_h reach (ground_truth.cpp)
}

bool hasNearLayer(const ImagePlane& plane, const SplatSettings& settings) {
    // Its kernels take the LUT's colour: shaded frames drop their eye kernels instead (near_layer.h).
    return !plane.orthographic && settings.shading == SplatSettings::Shading::None && settings.surfaceFlatten <= 1.0;
}

double splatNearReach(const ImagePlane& plane, const SplatSettings& settings) {
    return settings.cutoffSigmas * (hasNearLayer(plane, settings) ? kNearLayerDepths : 1.0);
}

NearTest nearTest(glm::dvec3 spacing, const ImagePlane& plane, const SplatSettings& settings) {
    const glm::dvec3 sigma = settings.kernelScale * spacing;
    NearTest t;
    t.nearDepth = plane.nearDepth;
    const double sigmaU2 = std::sqrt(kernelVarianceCamera(sigma, plane.viewFromObject)[2][2]);
    t.cutoffDepth = settings.cutoffSigmas * sigmaU2;
    t.reachDepth = splatNearReach(plane, settings) * sigmaU2;
    t.radius = settings.cutoffSigmas * std::max({sigma.x, sigma.y, sigma.z});
    // Pixel x spans [-reach, width + reach]: rays with u0 / u2 between (x - cx) / f at both ends.
    const double left = (-kFilterReachPx - plane.centrePx.x) / plane.fPx;
    const double right = (plane.width + kFilterReachPx - plane.centrePx.x) / plane.fPx;
    const double top = (-kFilterReachPx - plane.centrePx.y) / plane.fPx;
    const double bottom = (plane.height + kFilterReachPx - plane.centrePx.y) / plane.fPx;
    t.sides = {glm::normalize(glm::dvec3(-1.0, 0.0, left)), glm::normalize(glm::dvec3(1.0, 0.0, -right)),
               glm::normalize(glm::dvec3(0.0, -1.0, top)), glm::normalize(glm::dvec3(0.0, 1.0, -bottom))};
    return t;
}

VoxelBox nearCandidates(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing, const ImagePlane& plane,
                        const NearTest& test) {
    // Every accepted centre lies within rho of the eye: depth from near - cutoffDepth to near + reachDepth,
    // and sideways within the widened frustum at that depth.
    const double zMax = test.nearDepth + test.reachDepth;
    double rho2 = std::max(zMax, test.cutoffDepth - test.nearDepth);
    rho2 *= rho2;
    for (int axis = 0; axis < 2; ++axis) {
        double tanMax = 0.0; // the side planes' slopes, from their normals (n0, n1, n2): |n2 / n_axis|
        for (const glm::dvec3& n : test.sides)
            if (n[axis] != 0.0) tanMax = std::max(tanMax, std::abs(n.z / n[axis]));
        const double side = tanMax * zMax + test.radius * std::sqrt(1.0 + tanMax * tanMax);
        rho2 += side * side;
    }
    const double rho = std::sqrt(rho2);
    const glm::dvec3 eye = glm::transpose(plane.viewFromObject) * -plane.translation;
    VoxelBox box;
    const glm::dvec3 lo = glm::ceil((eye - rho - origin) / spacing),
                     hi = glm::floor((eye + rho - origin) / spacing);
    const glm::dvec3 last(dims - 1);
    if (!glm::all(glm::lessThanEqual(lo, last)) || !glm::all(glm::greaterThanEqual(hi, glm::dvec3(0.0))))
        return box;
    box.lo = glm::ivec3(glm::max(lo, glm::dvec3(0.0)));
    box.hi = glm::ivec3(glm::min(hi, last));
    return box;
}

NearKernels findNearKernels(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings) {
    NearKernels out;
    if (!hasNearLayer(plane, settings)) return out;
    const NearTest test = nearTest(scene.spacing, plane, settings);
    const VoxelBox box = nearCandidates(scene.dims, scene.origin, scene.spacing, plane, test);
    if (box.empty()) return out;
    const glm::ivec3 d = scene.dims;
    for (int z = box.lo.z; z <= box.hi.z; ++z)
        for (int y = box.lo.y; y <= box.hi.y; ++y)
            for (int x = box.lo.x; x <= box.hi.x; ++x) {
                const uint32_t i = uint32_t((size_t(z) * d.y + y) * d.x + x);
                if (!(scene.opacityOf(i) > 0.0f) ||
                    !test.accepts(plane.toCamera(scene.positionOf(i))))
                    continue;
                if (out.voxels.size() < size_t(kMaxNearKernels))
                    out.voxels.push_back(i);
                else
                    ++out.dropped;
            }
    return out;
}

NearSums nearLayerSums(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                       const NearKernels& kernels, int x, int y) {
    NearSums sums;
    if (kernels.voxels.empty()) return sums;
    // The pixel centre's ray from the eye, as the ground truth's (ground_truth.cpp), from the near plane on.
    const glm::dmat3 objectFromView = glm::transpose(plane.viewFromObject);
    const glm::dvec3 eye = objectFromView * -plane.translation;
    const glm::dvec2 m = (glm::dvec2(x + 0.5, y + 0.5) - plane.centrePx) / plane.fPx;
    const glm::dvec3 dirCamera = glm::normalize(glm::dvec3(m, 1.0));
    const glm::dvec3 dir = objectFromView * dirCamera;
    const double start = plane.nearDepth / dirCamera.z;
    const glm::dvec3 sigma = settings.kernelScale * scene.spacing;
    const double peak = kernelPeak(scene.spacing, sigma, settings.cutoffSigmas);
    const NearTest test = nearTest(scene.spacing, plane, settings);
    for (uint32_t voxel : kernels.voxels) {
        const auto k = kernelAlongRay(eye, dir, scene.positionOf(voxel), sigma, settings.cutoffSigmas, peak);
        if (!k) continue;
        const double tau = voxelExtinction(scene, settings, voxel) *
                           integrate(*k, start, std::numeric_limits<double>::infinity());
        (test.front(plane.toCamera(scene.positionOf(voxel))) ? sums.front : sums.back) +=
            glm::dvec4(scene.colourOf(voxel) * tau, tau);
    }
    return sums;
}

void compositeNearLayer(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                        const NearKernels& kernels, std::vector<double>& rgba) {
    if (kernels.voxels.empty()) return;
    const bool xray = settings.compositing == Compositing::XRay;
    tbb::parallel_for(0, plane.height, [&](int y) {
        for (int x = 0; x < plane.width; ++x) {
            const NearSums q = nearLayerSums(scene, plane, settings, kernels, x, y);
            double* p = &rgba[(size_t(y) * plane.width + x) * 4];
            for (const glm::dvec4& sheet : {q.back, q.front}) {   // back to front
                if (!(sheet.w > 0.0)) continue;
                if (xray) {
                    for (int c = 0; c < 4; ++c) p[c] += sheet[c];
                } else {
                    double c[3], a;
                    sheetColour(&sheet[0], c, a);
                    over(p, c, a);
                }
            }
        }
    });
}

Image imageWithNearLayer(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                         const NearKernels& kernels, std::vector<double> rgba) {
    compositeNearLayer(scene, plane, settings, kernels, rgba);
    Image img(plane.width, plane.height);
    for (size_t i = 0; i < rgba.size(); ++i) img.rgba[i] = float(rgba[i]);
    return img;
}

} // namespace renderer
