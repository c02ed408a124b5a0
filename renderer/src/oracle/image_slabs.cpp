// Image-aligned slabs on the CPU (see image_slabs.h). Per band of rows: kernels in order of their first
// slab; a ring of slab sheets holds the slabs a kernel can still reach, and each slab is composited
// under the image once no later kernel can reach it.
#include "renderer/oracle/image_slabs.h"

#include "renderer/errors.h"
#include "renderer/math/classifier.h"
#include "renderer/math/ewa.h"
#include "renderer/math/shading.h"
#include "renderer/model/post_classification.h"
#include "renderer/oracle/near_layer.h"
#include "renderer/oracle/pixel_filter.h"
#include "renderer/oracle/sheet_compositing.h"
#include "renderer/out_of_memory.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numbers>
#include <numeric>

namespace renderer {

namespace {
constexpr int kBand = 8;   // rows a worker composites together
} // namespace

void slabShares(double mean, double sd, double thickness, long first, int count, double* shares) {
    // Cumulative probability at each inner boundary; 0 before the first slab, 1 after the last.
    double below = 0.0;
    for (int i = 0; i < count; ++i) {
        const double end = double(first + i + 1) * thickness;
        double upTo = 1.0;
        if (i + 1 < count)
            upTo = sd > 0.0 ? 0.5 * std::erfc(-(end - mean) / (std::numbers::sqrt2 * sd)) : (mean < end ? 1.0 : 0.0);
        shares[i] = upTo - below;
        below = upTo;
    }
}

namespace {

struct SlabSplat {
    SplatGeometry geometry;
    glm::dvec3 colour;          // TF colour, shaded unless shading is per fragment (pre-classified)
    double value = 0.0;         // the voxel's class (post-classified)
    glm::dvec3 gradientCamera;  // per-fragment or post-classified shading
    double depth = 0.0;         // ray-space depth of the centre: |u|, or u2 orthographic
    glm::dvec2 depthSlope{0.0}; // conditional mean's change per pixel of offset: S_xy^-1 S_xyr
    double depthSd = 0.0;       // conditional standard deviation along the ray
    long first = 0, last = -1;  // slabs it can reach anywhere on its footprint
};

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

static Image renderSlabsOrThrow(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                                const SlabOptions& options, SlabCounters* counters) {
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
    const double perOpacity = extinctionPerOpacity(scene, settings);
    const double meanSpacing = (scene.spacing.x + scene.spacing.y + scene.spacing.z) / 3.0;
    const double slabUnits = thickness * meanSpacing;   // object units
    const double cutoff = settings.cutoffSigmas;
    const glm::dvec3 sigma = settings.kernelScale * scene.spacing;
    const glm::dmat3 varianceCamera = kernelVarianceCamera(sigma, plane.viewFromObject);
    const std::vector<uint8_t> modes =
        settings.filter == FilterMode::Adaptive ? patchModes(scene, plane, settings) : std::vector<uint8_t>{};
    const PatchGrid grid = patchGrid(scene.dims, chooseTraversal(plane).axis, settings.patchSize);

    // 1. Each visible kernel's footprint and depth law, in slab units. Post-classified every kernel is
    //    "visible": a transparent voxel's value still pulls the mean down.
    std::vector<uint32_t> visible;
    for (uint32_t voxel = 0; voxel < uint32_t(scene.classes.size()); ++voxel)
        if (post || scene.opacityOf(voxel) > 0.0f) visible.push_back(voxel);
    std::vector<SlabSplat> splats(visible.size());
    tbb::combinable<SplatCounters> perThread;
    tbb::parallel_for(size_t(0), visible.size(), [&](size_t k) {
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
    long ring = 1, front = 0, back = -1;
    for (const SlabSplat& s : splats) ring = std::max(ring, s.last - s.first + 1);
    if (!splats.empty()) {
        front = splats.front().first;
        for (const SlabSplat& s : splats) back = std::max(back, s.last);
    }
    // What a slab sums at a pixel, the weight last: pre-classified (c tau, tau); post-classified (v w, w),
    // shaded (v w, g w, w).
    const bool shaded = settings.shading != SplatSettings::Shading::None;
    const int stride = !post ? 4 : shaded ? 5 : 2;
    // Each worker holds `ring` sheets of a band of rows: bounded, or the thickness is refused by name.
    constexpr double kRingBudget = 1024.0 * 1024.0 * 1024.0;   // bytes, all workers together
    const double ringBytes = double(ring) * kBand * plane.width * stride * sizeof(double) *
                             double(tbb::this_task_arena::max_concurrency());
    if (ring > 4096 || ringBytes > kRingBudget) {
        char text[256];
        std::snprintf(text, sizeof text, "image-aligned slabs: a kernel spans %ld slabs of %g voxels, %.0f MiB of "
                      "slab sheets at %d px wide (at most 4096 slabs, %.0f MiB): take thicker slabs", ring, thickness,
                      ringBytes / (1024.0 * 1024.0), plane.width, kRingBudget / (1024.0 * 1024.0));
        throw RenderError(text);
    }
    SlabCounters total;
    total.splats.visible = visible.size();
    perThread.combine_each([&](const SplatCounters& c) { addCounters(total.splats, c); });
    total.slabs = splats.empty() ? 0 : uint64_t(back - front + 1);
    const NearKernels near = findNearKernels(scene, plane, settings);
    if (post && (!near.voxels.empty() || near.dropped > 0))
        throw RenderError("image-aligned slabs: post-classified, " + std::to_string(near.voxels.size() + near.dropped) +
                          " kernels in view reach the near plane (the near layer is pre-classified): move the camera back");
    total.splats.nearLayer = near.voxels.size();
    total.splats.droppedNear = near.dropped;

    // 2. Bands of rows; in each, a ring of `ring` slab sheets of `stride` sums per pixel.
    const int w = plane.width, h = plane.height;
    std::vector<double> acc(size_t(w) * h * 4, 0.0);
    const double cut2 = cutoff * cutoff;
    const bool perFragment = settings.shading == SplatSettings::Shading::PerFragment && !post;
    const bool earlyTermination = settings.opaqueAlpha < 1.0;
    tbb::combinable<std::pair<uint64_t, uint64_t>> work;   // footprint pixels, slab writes
    tbb::parallel_for(0, (h + kBand - 1) / kBand, [&](int band) {
        const int y0 = band * kBand, y1 = std::min(h, y0 + kBand);
        const size_t sheetSize = size_t(y1 - y0) * w * stride;
        std::vector<double> sheets(size_t(ring) * sheetSize, 0.0);
        std::vector<double> shares(static_cast<size_t>(ring));
        auto& [pixels, writes] = work.local();
        long next = front;   // the first slab not yet composited
        auto sheetOf = [&](long slab) { return &sheets[size_t(((slab % ring) + ring) % ring) * sheetSize]; };
        auto flushBefore = [&](long end) {
            for (; next < end; ++next) {
                double* q = sheetOf(next);
                for (int y = y0; y < y1; ++y)
                    for (int x = 0; x < w; ++x) {
                        double* sum = &q[(size_t(y - y0) * w + x) * stride];
                        if (sum[stride - 1] > 0.0) {
                            double c[3], a;
                            if (post) {   // classify the mean value, light the mean gradient
                                PostSample sample{.weight = sum[stride - 1], .valueSum = sum[0]};
                                if (shaded) sample.gradientSum = glm::dvec3(sum[1], sum[2], sum[3]);
                                const glm::dvec4 rgba = classifyPost(scene.lut, perOpacity, sample,
                                                                     shaded ? &settings.shadingParams : nullptr,
                                                                     toEyeAtPixel(x, y, plane));
                                c[0] = rgba.r, c[1] = rgba.g, c[2] = rgba.b, a = rgba.a;
                            } else {
                                sheetColour(sum, c, a);
                            }
                            under(&acc[(size_t(y) * w + x) * 4], c, a);
                        }
                        std::fill_n(sum, stride, 0.0);
                    }
            }
        };
        for (const SlabSplat& s : splats) {
            const SplatGeometry& g = s.geometry;
            const auto [xa, xb, ya, yb] = footprintBox(g, y0, y1, w);
            if (ya > yb) continue;
            flushBefore(s.first);
            const int count = int(s.last - s.first + 1);
            for (int y = ya; y <= yb; ++y)
                for (int x = xa; x <= xb; ++x) {
                    const glm::dvec2 d = glm::dvec2(x + 0.5, y + 0.5) - g.centrePx;
                    const double e = glm::dot(d, g.conic * d);
                    if (e > cut2) continue;
                    const size_t px = size_t(y) * w + x;
                    if (earlyTermination && acc[px * 4 + 3] >= settings.opaqueAlpha) continue;
                    ++pixels;
                    const double tau = g.amplitude * std::exp(-0.5 * e);
                    // What the kernel adds to each sum but the weight, in the layout of `stride`.
                    double adds[4] = {s.value, s.gradientCamera.x, s.gradientCamera.y, s.gradientCamera.z};
                    if (!post) {
                        const glm::dvec3 colour =
                            perFragment ? shadeAtPixel(s.colour, s.gradientCamera, x, y, plane, settings.shadingParams)
                                        : s.colour;
                        adds[0] = colour.r, adds[1] = colour.g, adds[2] = colour.b;
                    }
                    slabShares(s.depth + glm::dot(s.depthSlope, d), s.depthSd, 1.0, s.first, count, shares.data());
                    const size_t local = (size_t(y - y0) * w + x) * stride;
                    for (int i = 0; i < count; ++i) {
                        if (!(shares[size_t(i)] > 0.0)) continue;
                        double* q = sheetOf(s.first + i) + local;
                        const double t = tau * shares[size_t(i)];
                        for (int c = 0; c < stride - 1; ++c) q[c] += adds[c] * t;
                        q[stride - 1] += t;
                        ++writes;
                    }
                }
        }
        flushBefore(back + 1);
    });
    work.combine_each([&](const std::pair<uint64_t, uint64_t>& n) {
        total.footprintPixels += n.first;
        total.slabWrites += n.second;
    });
    if (counters) *counters = total;

    // 3. The near layer in front, as renderReference composites it.
    compositeNearLayer(scene, plane, settings, near, acc);
    Image img(w, h);
    for (size_t i = 0; i < acc.size(); ++i) img.rgba[i] = float(acc[i]);
    return img;
}

Image renderImageAlignedSlabs(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                              const SlabOptions& options, SlabCounters* counters) {
    if (options.supersample < 0 || options.supersample > kMaxSlabSupersample)
        throw RenderError("image-aligned slabs: supersample must be 0.." + std::to_string(kMaxSlabSupersample) +
                          ", got " + std::to_string(options.supersample));
    try {
        if (options.supersample == 0) return renderSlabsOrThrow(scene, plane, settings, options, counters);
        // The truth's sample grid (pixel_filter.h) as a finer image plane, then the truth's V_h resolve.
        const int ss = options.supersample, margin = pixelFilterMargin(ss);
        ImagePlane fine = plane;
        fine.width = plane.width * ss + 2 * margin;
        fine.height = plane.height * ss + 2 * margin;
        fine.fPx = plane.fPx * ss;
        fine.centrePx = plane.centrePx * double(ss) + double(margin);
        const Image samples = renderSlabsOrThrow(scene, fine, settings, options, counters);
        std::vector<glm::dvec4> wide(samples.rgba.size() / 4);
        for (size_t i = 0; i < wide.size(); ++i)
            wide[i] = glm::dvec4(samples.rgba[4 * i], samples.rgba[4 * i + 1], samples.rgba[4 * i + 2], samples.rgba[4 * i + 3]);
        return filterToPixels(wide, ss, plane.width, plane.height);
    } catch (const std::bad_alloc&) {
        throw outOfMemory(volumeSubject(scene.name), "image-aligned slabs' splats and sheets", 0,
                          " at " + std::to_string(plane.width) + "x" + std::to_string(plane.height));
    }
}

} // namespace renderer
