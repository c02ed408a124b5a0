// Step 1 of a frame: what it will draw and how, decided on the CPU before anything is issued (FramePlan):
// the view's axis, the program variant, tiles or the rasteriser, and each slice's primitive.
#include "splat_renderer_state.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace renderer {

namespace {

// An upper bound on the cutoff half extent, in pixels, of any splat of slice `slice` across `axis`:
// ||J||^2 <= ||J||_F^2 = (f/u2)^2 (2 + (u0^2 + u1^2) / u2^2) + 1, with u2 at least its smallest value
// over the slice's corners (u2 is linear) and u0^2 + u1^2 at most its largest (convex). Infinite when
// the slice reaches the near plane. Close up, the near slices need quads where the far ones fit
// points, and their rasterised sheets reach further.
double sliceHalfExtentBound(const glm::ivec3& dims, const glm::dvec3& origin, const glm::dvec3& spacing,
                            const ImagePlane& plane, const SplatSettings& settings, int axis, int slice) {
    double u2min = std::numeric_limits<double>::infinity(), lateral2 = 0.0;
    for (int c = 0; c < 4; ++c) {
        glm::dvec3 ijk(0.0);
        ijk[axis] = slice;
        ijk[(axis + 1) % 3] = (c & 1) ? dims[(axis + 1) % 3] - 1 : 0;
        ijk[(axis + 2) % 3] = (c & 2) ? dims[(axis + 2) % 3] - 1 : 0;
        const glm::dvec3 u = plane.toCamera(origin + spacing * ijk);
        u2min = std::min(u2min, u.z);
        lateral2 = std::max(lateral2, u.x * u.x + u.y * u.y);
    }
    double jacobian2 = 0.0;
    if (plane.orthographic) {
        jacobian2 = std::max(plane.fPx * plane.fPx, 1.0);
    } else {
        if (!(u2min > plane.nearDepth)) return std::numeric_limits<double>::infinity();
        const double g = plane.fPx / u2min;
        jacobian2 = g * g * (2.0 + lateral2 / (u2min * u2min)) + 1.0;
    }
    const double sigma = settings.kernelScale * std::max({spacing.x, spacing.y, spacing.z});
    return settings.cutoffSigmas * std::sqrt(jacobian2 * sigma * sigma + 1.0);
}

// Pixels a point sprite covers beyond a quad for the footprint at camera point u: the square around
// the ellipse's longer side against its box. Elongated footprints (anisotropic spacing) waste that
// fill; quads cost five more vertices instead. headsq (3.2 x 3.2 x 1.5 mm), llvmpipe, 512x512, full
// EWA, two rounds each: points were faster at distance 8 and 5 (41-51 and 100-142 px over the slices'
// centres), even at 3.5 and 2.5 (192-316, 348-699), 1.15x slower at 1.8 (605-1,630), 2.3x at 1.2.
constexpr double kPointExcessPx2 = 400.0;
double pointExcessPx2(glm::dvec3 u, const glm::dmat3& varianceCamera, const ImagePlane& plane,
                      const SplatSettings& settings, FilterMode filter) {
    const Footprint f = projectKernel(u, varianceCamera, plane.fPx, filter == FilterMode::Adaptive ? FilterMode::Ewa : filter,
                                      glm::dmat2(1.0), plane.orthographic);
    const double hx = settings.cutoffSigmas * std::sqrt(f.variancePx[0][0]);
    const double hy = settings.cutoffSigmas * std::sqrt(f.variancePx[1][1]);
    const double side = 2.0 * std::max(hx, hy) + 1.0;
    return side * side - (2.0 * hx + 1.0) * (2.0 * hy + 1.0);
}

} // namespace

FramePlan SplatRenderer::Gl::planFrame(const ImagePlane& plane, const SplatSettings& settings,
                                        bool rasterise) {
    Gl& g = *this;
    if (plane.width < 1 || plane.height < 1 || plane.width > 16384 || plane.height > 16384)
        throw RenderError("image size " + std::to_string(plane.width) + "x" + std::to_string(plane.height) +
                          " out of range (1..16384)");
    if (!g.classTexture) throw RenderError("SplatRenderer::render called before setScene");
    requireGradients(settings, g.hasGradients, g.sceneName);
    g.ensureTargets(plane.width, plane.height);

    using Primitive = SplatSettings::Primitive;
    if (settings.primitive == Primitive::Tiles && settings.compositing == Compositing::SplatEverySample)
        throw RenderError("tiled splatting composites sheets and X-ray only: splat-every-sample needs points or "
                          "quads (its order within a slice matters)");
    // Auto tiles sheets and X-ray. A chunk of slices whose lists do not fit the texel buffer they are
    // read through goes in parts, down to single slices; where one slice's do not fit, auto draws the
    // frame again rasterised (render()). (Deciding before the frame from a bound on footprint
    // size rasterised bonsai at distance 1.6 and nearer, 4-8x slower than tiles.)
    const Traversal trav = chooseTraversal(plane);
    const uint64_t listUpload = g.makeResident(trav.axis);
    const AxisBuffers& axis = g.axes[size_t(trav.axis)];
    std::array<bool, kBuckets> active = activeBuckets(g.lut);
    if (settings.drawAllBuckets) active.fill(true);
    // Splats each slice submits (its active runs' voxels), and the frame's.
    std::vector<uint64_t> sliceSubmitted(axis.sliceRuns.size() - 1, 0);
    for (size_t slice = 0; slice + 1 < axis.sliceRuns.size(); ++slice)
        for (uint32_t r = axis.sliceRuns[slice]; r < axis.sliceRuns[slice + 1]; ++r)
            sliceSubmitted[slice] += active[axis.buckets[r]] ? axis.voxels[r] : 0;
    const uint64_t submitted = std::accumulate(sliceSubmitted.begin(), sliceSubmitted.end(), uint64_t(0));
    const bool ftb = frontToBack(settings);
    const bool earlyTermination = ftb && settings.opaqueAlpha < 1.0;
    using Shading = SplatSettings::Shading;
    // Adaptive, where the volume's depth range puts every patch in one filter: that filter's code draws
    // the frame, and the patches are set to it without their pass (hysteresis reads them next frame).
    const FilterMode drawnFilter =
        settings.filter == FilterMode::Adaptive
            ? uniformAdaptiveFilter(g.dims, g.origin, g.spacing, plane, settings).value_or(FilterMode::Adaptive)
            : settings.filter;
    const int variant = (settings.counters ? kCounters : 0) | (settings.surfaceFlatten > 1.0 ? kSurface : 0) |
                        (settings.shading == Shading::PerSplat ? kSplatShading : 0) |
                        (settings.shading == Shading::PerFragment ? kFragmentShading : 0) |
                        (settings.heatmap ? kHeatmap : 0) | (drawnFilter == FilterMode::Adaptive ? kAdaptive : 0) |
                        (earlyTermination && settings.occlusionCulling ? kOcclusion : 0) |
                        (g.tf2d && g.hasGradients               ? kTf2d
                         : g.gradientOpacity && g.hasGradients ? kGradientOpacity
                                                                : 0);
    const bool tiles = settings.primitive == Primitive::Tiles || (tiledSplatting(settings) && !rasterise);
    // Rasterised, slice by slice: points cost one vertex and one primitive a splat instead of six and
    // two; they need the slice's footprints to fit the largest point size, and a guard band, since a
    // point is clipped by its centre. Auto and raster take quads for the other slices, and where the
    // slice's centre voxel says points would waste fill (pointExcessPx2()).
    const uint32_t slices = uint32_t(g.dims[trav.axis]);
    const double pointFits = 0.5 * (g.maxPointSize - 1.0);   // gl_PointSize = 2 h + 1
    const glm::dmat3 varianceCamera = kernelVarianceCamera(settings.kernelScale * g.spacing, plane.viewFromObject);
    std::vector<SliceDraw> sliceDraw(slices, kNothing);
    // Each drawn slice's bound on its footprints' half extent: also how far rasterised sheets reach.
    std::vector<double> sliceBound(slices, std::numeric_limits<double>::infinity());
    if (!tiles) {
        double worst = 0.0;
        for (uint32_t slice = 0; slice < slices; ++slice) {
            bool drawn = false;
            for (uint32_t r = axis.sliceRuns[slice]; r < axis.sliceRuns[slice + 1] && !drawn; ++r) drawn = active[axis.buckets[r]];
            if (!drawn) continue;
            const double b = sliceBound[slice] =
                sliceHalfExtentBound(g.dims, g.origin, g.spacing, plane, settings, trav.axis, int(slice));
            worst = std::max(worst, b);
            bool points = settings.primitive != Primitive::Quads && b <= pointFits;
            if (points && settings.primitive != Primitive::Points) {
                glm::dvec3 centre(0.0);
                centre[trav.axis] = slice;
                centre[(trav.axis + 1) % 3] = 0.5 * (g.dims[(trav.axis + 1) % 3] - 1);
                centre[(trav.axis + 2) % 3] = 0.5 * (g.dims[(trav.axis + 2) % 3] - 1);
                points = pointExcessPx2(plane.toCamera(g.origin + g.spacing * centre), varianceCamera, plane, settings,
                                        settings.filter) <= kPointExcessPx2;
            }
            sliceDraw[slice] = points ? kPoints : kQuads;
        }
        if (settings.primitive == Primitive::Points && std::count(sliceDraw.begin(), sliceDraw.end(), kQuads) > 0)
            throw RenderError("point sprites cannot hold this view's footprints (up to " + std::to_string(worst) +
                              " px half extent, the driver's points reach " + std::to_string(pointFits) + ")");
    }


    FramePlan f(plane, settings, axis);
    f.trav = trav;
    f.listUpload = listUpload;
    f.active = active;
    f.sliceSubmitted = std::move(sliceSubmitted);
    f.submitted = submitted;
    f.ftb = ftb;
    f.earlyTermination = earlyTermination;
    f.drawnFilter = drawnFilter;
    f.variant = variant;
    f.tiles = tiles;
    f.slices = slices;
    f.varianceCamera = varianceCamera;
    f.sliceDraw = std::move(sliceDraw);
    f.sliceBound = std::move(sliceBound);
    f.pointSlices = int(std::count(f.sliceDraw.begin(), f.sliceDraw.end(), kPoints));
    f.guard = f.pointSlices > 0 ? float(std::ceil(0.5 * g.maxPointSize) + 1.0) : 0.0f;
    const Compositing mode = settings.compositing;
    f.sheets = mode == Compositing::SheetBackToFront || mode == Compositing::SheetFrontToBack;
    f.reversed = ftb && !f.sheets;   // splat-every-sample, front to back: the exact reverse
    // Slices walk back to front, except front to back; sheets only turn the slice order, splat-every-
    // sample reverses everything (the vertex stage each run). Tiles read the commands by run.
    f.descending = trav.descending != (ftb && f.sheets);
    f.refresh = opaqueRefreshSlices(settings);
    f.xray = mode == Compositing::XRay;
    return f;
}

} // namespace renderer
