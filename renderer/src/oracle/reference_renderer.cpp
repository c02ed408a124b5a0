// The CPU oracle (see reference_renderer.h). Two phases: (1) every splat's geometry, in parallel;
// (2) compositing in draw order, parallel over bands of rows, so each pixel sees the splats in exactly
// the order the GL path blends them and the result does not depend on the thread count.
#include "renderer/oracle/reference_renderer.h"

#include "renderer/math/classifier.h"
#include "renderer/errors.h"
#include "renderer/math/shading.h"
#include "renderer/oracle/near_layer.h"
#include "renderer/oracle/sheet_compositing.h"
#include "renderer/out_of_memory.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <numbers>

namespace renderer {

PixelBox footprintBox(const SplatGeometry& g, int y0, int y1, int width) {
    return {std::max(0, int(std::ceil(g.centrePx.x - g.halfExtentPx.x - 0.5))),
            std::min(width - 1, int(std::floor(g.centrePx.x + g.halfExtentPx.x - 0.5))),
            std::max(y0, int(std::ceil(g.centrePx.y - g.halfExtentPx.y - 0.5))),
            std::min(y1 - 1, int(std::floor(g.centrePx.y + g.halfExtentPx.y - 0.5)))};
}

glm::dvec3 toEyeAtPixel(int x, int y, const ImagePlane& plane) {
    return toEyeAt(glm::dvec2(x + 0.5, y + 0.5), plane.centrePx, plane.fPx, plane.orthographic);
}

glm::dvec3 shadeAtPixel(glm::dvec3 colour, glm::dvec3 gradientCamera, int x, int y, const ImagePlane& plane,
                        const ShadingParams& params) {
    return shade(colour, gradientCamera, toEyeAtPixel(x, y, plane), params);
}

double voxelExtinction(const SplatScene& scene, const SplatSettings& settings, uint32_t voxel) {
    const double meanSpacing = (scene.spacing.x + scene.spacing.y + scene.spacing.z) / 3.0;
    return double(scene.opacityOf(voxel)) * settings.density / meanSpacing;
}

SplatGeometry splatGeometry(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                            uint32_t voxel, double extinction, FilterMode mode, SplatCounters* counters) {
    SplatGeometry g;
    g.culled = true;
    const glm::dvec3 u = plane.toCamera(scene.positionOf(voxel));
    if (!(u.z > plane.nearDepth)) {
        if (counters) ++counters->culledNear;
        return g;
    }
    const glm::dvec3 sigma = settings.kernelScale * scene.spacing;
    // Surface splats: the kernel flattened along the gradient; edge-on its reconstruction footprint
    // becomes a line, so without the low-pass filter its variance gets the pixel-sampling floor.
    bool surface = false;
    glm::dmat3 varCamera;
    if (settings.surfaceFlatten > 1.0 && !scene.gradients.empty()) {
        const DecodedGradient grad = decodeGradient(scene.gradients[voxel]);
        surface = grad.magnitude >= settings.surfaceGradient;
        varCamera = surface ? surfaceVarianceCamera(sigma, plane.viewFromObject, grad.normal, settings.surfaceFlatten)
                            : kernelVarianceCamera(sigma, plane.viewFromObject);
    } else {
        varCamera = kernelVarianceCamera(sigma, plane.viewFromObject);
    }
    // A kernel whose cutoff ellipsoid reaches the near plane is not splatted (counted as near): so close to
    // the eye EWA's local affine projection fails and its footprint would cover the image many times over
    // (the near-plane hard case: 16.3 dB drawn, 22.8 dB left out). The near layer integrates it along the
    // rays from the near plane on, as the truth does, and the kernels just behind it too (near_layer.h).
    const double nearReach = splatNearReach(plane, settings) * std::sqrt(varCamera[2][2]);
    if (!plane.orthographic && !(u.z - nearReach > plane.nearDepth)) {
        if (counters) ++counters->culledNear;
        return g;
    }
    Footprint f = projectKernel(u, varCamera, plane.fPx, mode, glm::dmat2(1.0), plane.orthographic);
    if (surface && mode == FilterMode::Reconstruction) {
        f.variancePx = clampFootprintVariance(f.variancePx);
        f.peak = f.jacobianDet / (2.0 * std::numbers::pi * std::sqrt(glm::determinant(f.variancePx)));
    }
    const double det = glm::determinant(f.variancePx);
    if (!(det > 1e-12)) {
        if (counters) ++counters->culledDegenerate;
        return g;
    }
    g.centrePx = plane.centrePx + f.offsetPx;   // == plane.project(u)
    g.conic = glm::inverse(f.variancePx);
    g.halfExtentPx = settings.cutoffSigmas * glm::sqrt(glm::dvec2(f.variancePx[0][0], f.variancePx[1][1]));
    const double diagonal = std::hypot(double(plane.width), double(plane.height));
    if (settings.maxFootprintFraction > 0.0 &&
        std::max(g.halfExtentPx.x, g.halfExtentPx.y) > settings.maxFootprintFraction * diagonal) {
        if (counters) ++counters->culledHuge;
        return g;
    }
    if (g.centrePx.x + g.halfExtentPx.x < 0 || g.centrePx.x - g.halfExtentPx.x > plane.width ||
        g.centrePx.y + g.halfExtentPx.y < 0 || g.centrePx.y - g.halfExtentPx.y > plane.height) {
        if (counters) ++counters->culledOffscreen;
        return g;
    }
    // Optical depth at the centre: extinction x voxel volume x line integral of the unit-mass kernel.
    // The voxel volume makes sum_k r_k a partition of unity, so g(t) interpolates the extinction; the
    // cutoff's lost mass is given back (footprintMassWithin), as the ground truth gives back its own.
    const double voxelVolume = scene.spacing.x * scene.spacing.y * scene.spacing.z;
    g.amplitude = extinction * voxelVolume * f.peak / footprintMassWithin(settings.cutoffSigmas);

    g.culled = false;
    if (counters) ++counters->drawn, ++counters->drawnPerMode[int(mode)];
    return g;
}

namespace {

struct Splat {
    SplatGeometry geometry;
    glm::dvec3 colour;          // TF colour, shaded unless shading is per fragment
    glm::dvec3 gradientCamera;  // per-fragment shading: W times the decoded relative gradient
    int mode = 0;               // resolved filter, for the heatmap
};


} // namespace

void addCounters(SplatCounters& a, const SplatCounters& b) {
    a.drawn += b.drawn;
    a.culledTransparent += b.culledTransparent;
    a.culledNear += b.culledNear;
    a.culledOffscreen += b.culledOffscreen;
    a.culledHuge += b.culledHuge;
    a.culledDegenerate += b.culledDegenerate;
    a.culledOccluded += b.culledOccluded;
    a.nearLayer += b.nearLayer;
    a.droppedNear += b.droppedNear;
    for (int m = 0; m < 3; ++m) a.drawnPerMode[m] += b.drawnPerMode[m];
}

std::vector<uint8_t> patchModes(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                                const std::vector<uint8_t>* previous) {
    const Traversal trav = chooseTraversal(plane);
    const glm::ivec3 d = scene.dims;
    const PatchGrid grid = patchGrid(d, trav.axis, settings.patchSize);
    const int a = (trav.axis + 1) % 3, b = (trav.axis + 2) % 3, p = grid.size;
    const AdaptiveThresholds t = adaptiveThresholds(scene.spacing, plane, settings);
    std::vector<uint8_t> modes(grid.count());
    const bool hasPrevious = previous && previous->size() == modes.size() && settings.hysteresis > 0.0;
    tbb::parallel_for(0, d[trav.axis], [&](int slice) {
        for (int pb = 0; pb < grid.rows; ++pb)
            for (int pa = 0; pa < grid.columns; ++pa) {
                glm::ivec3 v;
                v[trav.axis] = slice;
                v[a] = pa * p;
                v[b] = pb * p;
                const uint32_t voxel = uint32_t((v.z * d.y + v.y) * d.x + v.x);
                const size_t i = grid.indexOf(v);
                modes[i] = settings.filter != FilterMode::Adaptive
                               ? uint8_t(settings.filter)
                               : uint8_t(classifyPatch(scene, plane, t, p, trav.axis, voxel,
                                                       hasPrevious ? FilterMode((*previous)[i]) : FilterMode::Adaptive,
                                                       settings.hysteresis));
            }
    });
    return modes;
}

static Image renderReferenceOrThrow(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                                   SplatCounters* counters, Image* heatmap,
                                   const std::vector<uint8_t>* previousPatchModes) {
    const Compositing mode = settings.compositing;
    const bool sheets = mode == Compositing::SheetBackToFront || mode == Compositing::SheetFrontToBack;
    const bool ftb = frontToBack(settings);
    const bool earlyTermination = ftb && settings.opaqueAlpha < 1.0;
    const Traversal trav = chooseTraversal(plane);
    requireGradients(settings, scene.gradients.size() == scene.classes.size(), scene.name);
    std::vector<uint32_t> sliceStarts;
    std::vector<uint32_t> order = drawOrder(scene, trav, ftb && sheets, settings.drawAllBuckets, &sliceStarts);
    const size_t n = order.size();
    const size_t slices = sliceStarts.size() - 1;
    if (ftb && !sheets) {   // splat-every-sample front to back: the exact reverse of back to front
        std::reverse(order.begin(), order.end());
        std::vector<uint32_t> starts(slices + 1);
        for (size_t j = 0; j <= slices; ++j) starts[j] = uint32_t(n - sliceStarts[slices - j]);
        sliceStarts = std::move(starts);
    }

    // 1. Geometry of every splat, in draw order; adaptive filters come from one classification a patch.
    const std::vector<uint8_t> modes = settings.filter == FilterMode::Adaptive
                                           ? patchModes(scene, plane, settings, previousPatchModes)
                                           : std::vector<uint8_t>{};
    const PatchGrid grid = patchGrid(scene.dims, trav.axis, settings.patchSize);
    std::vector<Splat> splats(n);
    tbb::combinable<SplatCounters> perThread;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
        auto& c = perThread.local();
        for (size_t k = r.begin(); k != r.end(); ++k) {
            const uint32_t voxel = order[k];
            if (!(scene.opacityOf(voxel) > 0.0f)) {
                splats[k].geometry.culled = true;
                ++c.culledTransparent;
                continue;
            }
            FilterMode m = settings.filter;
            if (m == FilterMode::Adaptive) {
                const glm::uvec3 d(scene.dims);
                const glm::ivec3 v(int(voxel % d.x), int(voxel / d.x % d.y), int(voxel / (d.x * d.y)));
                m = FilterMode(modes[grid.indexOf(v)]);
            }
            splats[k].geometry =
                splatGeometry(scene, plane, settings, voxel, voxelExtinction(scene, settings, voxel), m, &c);
            splats[k].colour = scene.colourOf(voxel);
            splats[k].mode = int(m);
            if (settings.shading != SplatSettings::Shading::None) {
                splats[k].gradientCamera = plane.viewFromObject * decodeGradient(scene.gradients[voxel]).gradient();
                if (settings.shading == SplatSettings::Shading::PerSplat)   // towards the eye from the centre
                    splats[k].colour = shade(splats[k].colour, splats[k].gradientCamera,
                                             -plane.toCamera(scene.positionOf(voxel)), settings.shadingParams);
            }
        }
    });
    SplatCounters total;
    total.visible = n;
    perThread.combine_each([&](const SplatCounters& c) { addCounters(total, c); });
    const NearKernels near = findNearKernels(scene, plane, settings);
    total.nearLayer = near.voxels.size();
    total.droppedNear = near.dropped;
    if (counters) *counters = total;

    // 2. Composite bands of rows; each band walks all splats in order and touches only its rows.
    //    Two layers per pixel: the image and the heatmap (the same compositing of one-hot mode colours).
    const int w = plane.width, h = plane.height;
    const int layers = heatmap ? 2 : 1;
    std::vector<double> acc(size_t(layers) * w * h * 4, 0.0);
    const size_t layerSize = size_t(w) * h * 4;
    const double cut2 = settings.cutoffSigmas * settings.cutoffSigmas;
    const bool perFragment = settings.shading == SplatSettings::Shading::PerFragment;
    // Early termination: which pixels are opaque is refreshed every `refresh` slices; a band of rows
    // is one row of opaque tiles, whose state at each refresh the occlusion count reads afterwards.
    constexpr int kBand = kOpaqueTilePx;
    const size_t refresh = size_t(opaqueRefreshSlices(settings));
    const int tilesX = (w + kOpaqueTilePx - 1) / kOpaqueTilePx, tilesY = (h + kBand - 1) / kBand;
    std::vector<uint8_t> tileSnapshots(earlyTermination ? (slices / refresh + 1) * tilesX * tilesY : 0, 0);
    tbb::parallel_for(0, (h + kBand - 1) / kBand, [&](int band) {
        const int y0 = band * kBand, y1 = std::min(h, y0 + kBand);
        const size_t bandSize = size_t(y1 - y0) * w * 4;
        // Sheet buffer of this band, per layer: (sum c tau, sum tau) of the current slice.
        std::vector<double> sheet(sheets ? layers * bandSize : 0, 0.0);
        std::vector<char> opaque(earlyTermination ? size_t(y1 - y0) * w : 0, 0);
        auto refreshOpaque = [&](size_t group) {
            uint8_t* tiles = &tileSnapshots[(group * tilesY + band) * tilesX];
            std::fill_n(tiles, tilesX, uint8_t(1));
            for (int y = y0; y < y1; ++y)
                for (int x = 0; x < w; ++x) {
                    const bool o = acc[(size_t(y) * w + x) * 4 + 3] >= settings.opaqueAlpha;
                    opaque[size_t(y - y0) * w + x] = o;
                    if (!o) tiles[x / kOpaqueTilePx] = 0;
                }
        };
        auto flushSheet = [&] {
            for (int y = y0; y < y1; ++y)
                for (int x = 0; x < w; ++x) {
                    const size_t local = size_t(y - y0) * w + x;
                    double* q = &sheet[local * 4];
                    if (q[3] > 0.0) {
                        for (int l = 0; l < layers; ++l) {
                            double c[3], a;
                            sheetColour(q + l * bandSize, c, a);
                            double* p = &acc[l * layerSize + (size_t(y) * w + x) * 4];
                            if (ftb) under(p, c, a);   // what is in front is already in p
                            else over(p, c, a);
                        }
                    }
                    for (int l = 0; l < layers; ++l) std::fill_n(q + l * bandSize, 4, 0.0);
                }
        };
        size_t slice = 0;   // in draw order
        for (size_t k = 0; k < n; ++k) {
            if (k == sliceStarts[slice + 1]) {
                if (sheets) flushSheet();
                const size_t before = slice;
                while (k == sliceStarts[slice + 1]) ++slice;
                // A snapshot for every refresh crossed: occlusion may read one whose slices were empty.
                if (earlyTermination)
                    for (size_t group = before / refresh + 1; group <= slice / refresh; ++group) refreshOpaque(group);
            }
            const Splat& s = splats[k];
            const SplatGeometry& g = s.geometry;
            if (g.culled) continue;
            const auto [xa, xb, ya, yb] = footprintBox(g, y0, y1, w);
            if (ya > yb) continue;
            const double heat[3] = {s.mode == 0 ? 1.0 : 0.0, s.mode == 1 ? 1.0 : 0.0, s.mode == 2 ? 1.0 : 0.0};
            for (int y = ya; y <= yb; ++y)
                for (int x = xa; x <= xb; ++x) {
                    const glm::dvec2 d = glm::dvec2(x + 0.5, y + 0.5) - g.centrePx;
                    const double e = glm::dot(d, g.conic * d);
                    if (e > cut2) continue;
                    if (earlyTermination && opaque[size_t(y - y0) * w + x]) continue;
                    const double tau = g.amplitude * std::exp(-0.5 * e);
                    const glm::dvec3 shaded =
                        perFragment ? shadeAtPixel(s.colour, s.gradientCamera, x, y, plane, settings.shadingParams) : s.colour;
                    for (int l = 0; l < layers; ++l) {
                        const double* colour = l == 0 ? &shaded[0] : heat;
                        double* p = sheets ? &sheet[l * bandSize + (size_t(y - y0) * w + x) * 4]
                                           : &acc[l * layerSize + (size_t(y) * w + x) * 4];
                        if (sheets || mode == Compositing::XRay) {
                            for (int c = 0; c < 3; ++c) p[c] += colour[c] * tau;
                            p[3] += tau;
                        } else {
                            const double a = -std::expm1(-tau);
                            if (ftb) {   // "under", front to back
                                for (int c = 0; c < 3; ++c) p[c] += (1.0 - p[3]) * colour[c] * a;
                                p[3] += (1.0 - p[3]) * a;
                            } else {
                                const double c[3] = {colour[0] * a, colour[1] * a, colour[2] * a};
                                over(p, c, a);   // back to front, premultiplied
                            }
                        }
                    }
                }
        }
        if (sheets) flushSheet();
    });

    // Occlusion culling as the GPU does it: a splat is culled when every tile under its pixel box (at
    // most 4 x 4) was opaque at the snapshot its slice reads, taken where its chunk starts (chunks as
    // nextOcclusionChunk() lays them out). Its pixels were all skipped above, so only the counters change.
    if (earlyTermination && counters && settings.occlusionCulling) {
        const size_t mapSize = size_t(tilesX) * tilesY;
        auto anyOpaque = [&](size_t group) {
            const uint8_t* tiles = &tileSnapshots[group * mapSize];
            return std::any_of(tiles, tiles + mapSize, [](uint8_t t) { return t != 0; });
        };
        std::vector<size_t> chunkStart(slices, 0);
        for (size_t start = 0, chunk = size_t(occlusionSlices(settings)); start < slices;) {
            std::fill(chunkStart.begin() + std::ptrdiff_t(start),
                      chunkStart.begin() + std::ptrdiff_t(std::min(slices, start + chunk)), start);
            start += chunk;
            if (start < slices) chunk = size_t(nextOcclusionChunk(settings, int(start), int(chunk), anyOpaque(start / refresh)));
        }
        for (size_t j = 0; j < slices; ++j)
            for (size_t k = sliceStarts[j]; k < sliceStarts[j + 1] && chunkStart[j] > 0; ++k) {
                const SplatGeometry& g = splats[k].geometry;
                if (g.culled) continue;
                const glm::dvec2 lo = glm::ceil(g.centrePx - g.halfExtentPx - 0.5);
                const glm::dvec2 hi = glm::floor(g.centrePx + g.halfExtentPx - 0.5);
                const int ta = std::clamp(int(lo.x), 0, w - 1) / kOpaqueTilePx, tb = std::clamp(int(hi.x), 0, w - 1) / kOpaqueTilePx;
                const int sa = std::clamp(int(lo.y), 0, h - 1) / kOpaqueTilePx, sb = std::clamp(int(hi.y), 0, h - 1) / kOpaqueTilePx;
                if (tb - ta >= 4 || sb - sa >= 4) continue;
                const uint8_t* tiles = &tileSnapshots[chunkStart[j] / refresh * mapSize];
                bool hidden = true;
                for (int ty = sa; ty <= sb; ++ty)
                    for (int tx = ta; tx <= tb; ++tx) hidden = hidden && tiles[ty * tilesX + tx];
                if (!hidden) continue;
                ++counters->culledOccluded;
                --counters->drawn;
                --counters->drawnPerMode[splats[k].mode];
            }
    }

    // 3. The near layer in front of the splats (near_layer.h): over the image, or into X-ray's sums. The
    //    heatmap shows splats only.
    const bool xray = mode == Compositing::XRay;
    compositeNearLayer(scene, plane, settings, near, acc);   // the first layer of acc: the image

    // X-ray shows 1 - exp(-sum); its heatmap splits that alpha by each mode's share of the sum.
    Image img(w, h);
    for (size_t i = 0; i < layerSize; ++i) img.rgba[i] = float(xray ? -std::expm1(-acc[i]) : acc[i]);
    if (heatmap) {
        *heatmap = Image(w, h);
        for (size_t px = 0; px < size_t(w) * h; ++px) {
            const double* q = &acc[layerSize + px * 4];
            const double a = xray ? -std::expm1(-q[3]) : q[3];
            const double scale = xray ? (q[3] > 0.0 ? a / q[3] : 0.0) : 1.0;
            for (int k = 0; k < 3; ++k) heatmap->rgba[px * 4 + k] = float(q[k] * scale);
            heatmap->rgba[px * 4 + 3] = float(a);
        }
    }
    return img;
}

// An allocation that fails (the splats' geometry, the image) names the volume and the view's size.
Image renderReference(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                      SplatCounters* counters, Image* heatmap, const std::vector<uint8_t>* previousPatchModes) {
    try {
        return renderReferenceOrThrow(scene, plane, settings, counters, heatmap, previousPatchModes);
    } catch (const std::bad_alloc&) {
        throw outOfMemory(volumeSubject(scene.name), "CPU reference's splats and image", 0,
                          " at " + std::to_string(plane.width) + "x" + std::to_string(plane.height));
    }
}

} // namespace renderer
