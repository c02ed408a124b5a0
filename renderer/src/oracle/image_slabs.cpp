// Image-aligned slabs on the CPU (see image_slabs.h). Per band of rows: kernels in order of their first
// slab; a ring of slab sheets holds the slabs a kernel can still reach, and each slab is composited
// under the image once no later kernel can reach it.
#include "renderer/oracle/image_slabs.h"
#include "renderer/oracle/slab_setup.h"

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
#include <utility>
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

static Image renderSlabsOrThrow(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                                const SlabOptions& options, SlabCounters* counters) {
    const SlabSetup setup = prepareSlabs(scene, plane, settings, options);
    const std::vector<SlabSplat>& splats = setup.splats;
    const long ring = setup.ring, front = setup.front, back = setup.back;
    const bool post = setup.post, shaded = setup.shaded, perFragment = setup.perFragment;
    const int stride = setup.stride;
    const double perOpacity = setup.perOpacity, thickness = options.thickness;
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
    SlabCounters total = setup.counters;

    // Bands of rows; in each, a ring of `ring` slab sheets of `stride` sums per pixel.
    const int w = plane.width, h = plane.height;
    std::vector<double> acc(size_t(w) * h * 4, 0.0);
    const double cut2 = settings.cutoffSigmas * settings.cutoffSigmas;
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

    // The near layer in front, as renderReference composites it.
    return imageWithNearLayer(scene, plane, settings, setup.near, std::move(acc));
}

Image renderImageAlignedSlabs(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                              const SlabOptions& options, SlabCounters* counters) {
    requireSlabSupersample(options.supersample);
    try {
        return renderSupersampled(plane, options.supersample, [&](const ImagePlane& p) {
            return renderSlabsOrThrow(scene, p, settings, options, counters);
        });
    } catch (const std::bad_alloc&) {
        throw outOfMemory(volumeSubject(scene.name), "image-aligned slabs' splats and sheets", 0,
                          " at " + std::to_string(plane.width) + "x" + std::to_string(plane.height));
    }
}

} // namespace renderer
