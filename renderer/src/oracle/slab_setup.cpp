// Each kernel's footprint and depth law for the image-aligned slabs (see slab_setup.h).
#include "renderer/oracle/slab_setup.h"

#include "renderer/errors.h"
#include "renderer/math/classifier.h"
#include "renderer/math/ewa.h"
#include "renderer/math/shading.h"
#include "renderer/model/post_classification.h"
#include "renderer/oracle/post_reach.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace renderer {

namespace {

// The ray-space variance of a kernel and the conditional law of its depth along a pixel's ray.
// Depths are returned in slabs of `slabUnits` object units.
void depthAlongRays(SlabSplat& s, glm::dvec3 u, const glm::dmat3& varianceCamera, const ImagePlane& plane,
                    FilterMode mode, double cutoff, double slabUnits) {
    const glm::dmat3 j = plane.orthographic
                             ? glm::dmat3(glm::dvec3(plane.fPx, 0, 0), glm::dvec3(0, plane.fPx, 0), glm::dvec3(0, 0, 1))
                             : rayJacobianPx(u, plane.fPx);
    const glm::dmat3 v = j * varianceCamera * glm::transpose(j);
    s.depth = plane.orthographic ? u.z : glm::length(u);
    const double varDepth = v[2][2];
    if (mode == FilterMode::LowPass) {   // the kernel's depth profile under the V_h footprint
        s.depthSlope = glm::dvec2(0.0);
        s.depthSd = std::sqrt(std::max(0.0, varDepth));
    } else {
        const glm::dvec2 cross(v[2][0], v[2][1]);   // S_xyr
        s.depthSlope = s.geometry.conic * cross;    // conic = (S_xy [+ V_h])^-1, symmetric
        s.depthSd = std::sqrt(std::max(0.0, varDepth - glm::dot(cross, s.depthSlope)));
    }
    s.depth /= slabUnits;
    s.depthSlope /= slabUnits;
    s.depthSd /= slabUnits;
    // Over the cutoff ellipse d^T conic d <= c^2 the slope term is at most c sqrt(w^T conic^-1 w).
    const double spread = cutoff * std::sqrt(std::max(0.0, glm::dot(s.depthSlope, glm::inverse(s.geometry.conic) * s.depthSlope)));
    s.first = long(std::floor(s.depth - spread - cutoff * s.depthSd));
    s.last = long(std::floor(s.depth + spread + cutoff * s.depthSd));
}

} // namespace


void requireSlabSupersample(int supersample) {
    if (supersample < 0 || supersample > kMaxSlabSupersample)
        throw RenderError("image-aligned slabs: supersample must be 0.." + std::to_string(kMaxSlabSupersample) +
                          ", got " + std::to_string(supersample));
}

SlabSetup prepareSlabs(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                       const SlabOptions& options, const std::function<bool()>& interrupted) {
    const double thickness = options.thickness;
    const bool post = options.postClassified;
    if (settings.compositing == Compositing::XRay)
        throw RenderError("image-aligned slabs: X-ray compositing has no order to slice (use a sheet or "
                          "splat-every-sample compositing)");
    if (settings.surfaceFlatten > 1.0)
        throw RenderError("image-aligned slabs: surface splats are not modelled (surface flatten must be 1)");
    if (!(thickness >= kMinSlabThickness && thickness <= kMaxSlabThickness))
        throw RenderError("image-aligned slabs: thickness " + std::to_string(thickness) + " voxels is outside [" +
                          std::to_string(kMinSlabThickness) + ", " + std::to_string(kMaxSlabThickness) + "]");
    requireGradients(settings, scene.gradients.size() == scene.classes.size(), scene.name);
    if (post) requirePostClassifiable(scene, settings, "image-aligned slabs");
    SlabSetup out;
    out.perOpacity = extinctionPerOpacity(scene, settings);
    const double meanSpacing = (scene.spacing.x + scene.spacing.y + scene.spacing.z) / 3.0;
    const double slabUnits = thickness * meanSpacing;   // object units
    const double cutoff = settings.cutoffSigmas;
    const glm::dvec3 sigma = settings.kernelScale * scene.spacing;
    const glm::dmat3 varianceCamera = kernelVarianceCamera(sigma, plane.viewFromObject);
    const std::vector<uint8_t> modes =
        settings.filter == FilterMode::Adaptive ? patchModes(scene, plane, settings) : std::vector<uint8_t>{};
    const PatchGrid grid = patchGrid(scene.dims, chooseTraversal(plane).axis, settings.patchSize);

    // Each visible kernel's footprint and depth law, in slab units. Post-classified every kernel is
    //    "visible": a transparent voxel's value still pulls the mean down.
    //    Those whose whole neighbourhood is transparent change no pixel (post_reach.h): skipped.
    const std::vector<uint8_t> nearVisible = post && options.cullTransparent
                                                 ? kernelsNearVisible(scene, postReach(scene, plane, settings, slabUnits))
                                                 : std::vector<uint8_t>{};
    std::vector<uint32_t> visible;
    for (uint32_t voxel = 0; voxel < uint32_t(scene.classes.size()); ++voxel)
        if (post ? nearVisible.empty() || nearVisible[voxel] : scene.opacityOf(voxel) > 0.0f) visible.push_back(voxel);
    std::vector<SlabSplat> splats(visible.size());
    tbb::combinable<SplatCounters> perThread;
    tbb::parallel_for(size_t(0), visible.size(), [&](size_t k) {
        constexpr size_t kInterruptEvery = 4096;   // kernels: the check takes a lock, a kernel microseconds
        if (interrupted && k % kInterruptEvery == 0 && interrupted())
            throw Cancelled("image-aligned slabs: superseded");
        const uint32_t voxel = visible[k];
        FilterMode m = settings.filter;
        if (m == FilterMode::Adaptive) {
            const glm::uvec3 d(scene.dims);
            m = FilterMode(modes[grid.indexOf(glm::ivec3(int(voxel % d.x), int(voxel / d.x % d.y), int(voxel / (d.x * d.y))))]);
        }
        SlabSplat& s = splats[k];
        // Post-classified the footprint carries the kernel's weight (extinction 1).
        s.geometry = splatGeometry(scene, plane, settings, voxel, post ? 1.0 : voxelExtinction(scene, settings, voxel), m,
                                   &perThread.local());
        if (s.geometry.culled) return;
        const glm::dvec3 u = plane.toCamera(scene.positionOf(voxel));
        depthAlongRays(s, u, varianceCamera, plane, m, cutoff, slabUnits);
        s.colour = scene.colourOf(voxel);
        s.value = scene.classes[voxel];
        if (settings.shading != SplatSettings::Shading::None) {
            s.gradientCamera = plane.viewFromObject * decodeGradient(scene.gradients[voxel]).gradient();
            if (settings.shading == SplatSettings::Shading::PerSplat && !post)
                s.colour = shade(s.colour, s.gradientCamera, -u, settings.shadingParams);
        }
    });
    std::erase_if(splats, [](const SlabSplat& s) { return s.geometry.culled; });
    std::stable_sort(splats.begin(), splats.end(), [](const SlabSplat& a, const SlabSplat& b) { return a.first < b.first; });
    out.splats = std::move(splats);
    for (const SlabSplat& s : out.splats) out.ring = std::max(out.ring, s.last - s.first + 1);
    if (!out.splats.empty()) {
        out.front = out.splats.front().first;
        for (const SlabSplat& s : out.splats) out.back = std::max(out.back, s.last);
    }
    out.post = post;
    out.shaded = settings.shading != SplatSettings::Shading::None;
    out.perFragment = settings.shading == SplatSettings::Shading::PerFragment && !post;
    out.stride = !post ? 4 : out.shaded ? 5 : 2;
    SlabCounters& total = out.counters;
    total.splats.visible = visible.size();
    if (!nearVisible.empty()) total.skippedTransparent = scene.classes.size() - visible.size();
    perThread.combine_each([&](const SplatCounters& c) { addCounters(total.splats, c); });
    total.slabs = out.splats.empty() ? 0 : uint64_t(out.back - out.front + 1);
    out.near = findNearKernels(scene, plane, settings);
    if (post && (!out.near.voxels.empty() || out.near.dropped > 0))
        throw RenderError("image-aligned slabs: post-classified, " +
                          std::to_string(out.near.voxels.size() + out.near.dropped) +
                          " kernels in view reach the near plane (the near layer is pre-classified): move the camera back");
    total.splats.nearLayer = out.near.voxels.size();
    total.splats.droppedNear = out.near.dropped;
    return out;

}

} // namespace renderer
