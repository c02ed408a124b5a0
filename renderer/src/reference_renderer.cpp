// The CPU oracle (see reference_renderer.h). Two phases: (1) every splat's geometry, in parallel;
// (2) compositing in draw order, parallel over bands of rows, so each pixel sees the splats in exactly
// the order the GL path blends them and the result does not depend on the thread count.
#include "renderer/reference_renderer.h"

#include "renderer/classifier.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <climits>
#include <cmath>

namespace renderer {

double extinctionOf(const SplatScene& scene, const SplatSettings& settings, uint16_t cls) {
    const double meanSpacing = (scene.spacing.x + scene.spacing.y + scene.spacing.z) / 3.0;
    return double(scene.lut[cls].a) * settings.density / meanSpacing;
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
    const glm::dmat3 varCamera = kernelVarianceCamera(settings.kernelScale * scene.spacing, plane.viewFromObject);
    const Footprint f = projectKernel(u, varCamera, plane.fPx, mode, glm::dmat2(1.0), plane.orthographic);
    const double det = glm::determinant(f.variancePx);
    if (!(det > 1e-12)) {
        if (counters) ++counters->culledDegenerate;
        return g;
    }
    g.centrePx = plane.centrePx + f.offsetPx;   // == plane.project(u)
    g.conic = glm::inverse(f.variancePx);
    g.halfExtentPx = settings.cutoffSigmas * glm::sqrt(glm::dvec2(f.variancePx[0][0], f.variancePx[1][1]));
    const double diagonal = std::hypot(double(plane.width), double(plane.height));
    if (std::max(g.halfExtentPx.x, g.halfExtentPx.y) > settings.maxFootprintFraction * diagonal) {
        if (counters) ++counters->culledHuge;
        return g;
    }
    if (g.centrePx.x + g.halfExtentPx.x < 0 || g.centrePx.x - g.halfExtentPx.x > plane.width ||
        g.centrePx.y + g.halfExtentPx.y < 0 || g.centrePx.y - g.halfExtentPx.y > plane.height) {
        if (counters) ++counters->culledOffscreen;
        return g;
    }
    // Optical depth at the centre: extinction x voxel volume x line integral of the unit-mass kernel.
    // The voxel volume makes sum_k r_k a partition of unity, so g(t) interpolates the extinction.
    const double voxelVolume = scene.spacing.x * scene.spacing.y * scene.spacing.z;
    g.amplitude = extinction * voxelVolume * f.peak;
    g.culled = false;
    if (counters) ++counters->drawn, ++counters->drawnPerMode[int(mode)];
    return g;
}

namespace {

struct Splat {
    SplatGeometry geometry;
    glm::dvec3 colour;
    int slice = 0;   // coordinate along the traversal axis
};

void addCounters(SplatCounters& a, const SplatCounters& b) {
    a.drawn += b.drawn;
    a.culledNear += b.culledNear;
    a.culledOffscreen += b.culledOffscreen;
    a.culledHuge += b.culledHuge;
    a.culledDegenerate += b.culledDegenerate;
    for (int m = 0; m < 3; ++m) a.drawnPerMode[m] += b.drawnPerMode[m];
}

// "Over" of premultiplied (c, a) onto what lies behind it.
inline void over(double* dst, const double* c, double a) {
    for (int k = 0; k < 3; ++k) dst[k] = c[k] + (1.0 - a) * dst[k];
    dst[3] = a + (1.0 - a) * dst[3];
}

} // namespace

Image renderReference(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                      SplatCounters* counters) {
    const Traversal trav = chooseTraversal(plane);
    const auto& list = scene.visible[trav.axis];
    const size_t n = list.size();

    // 1. Geometry of every splat, in draw order (back to front; sheet front-to-back walks it reversed).
    const AdaptiveThresholds thresholds = adaptiveThresholds(scene.spacing, plane, settings);
    std::vector<Splat> splats(n);
    tbb::combinable<SplatCounters> perThread;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
        auto& c = perThread.local();
        for (size_t k = r.begin(); k != r.end(); ++k) {
            const uint32_t voxel = list[trav.descending ? n - 1 - k : k];
            const uint16_t cls = scene.classes[voxel];
            const FilterMode mode = resolveFilter(scene, plane, settings, thresholds, trav.axis, voxel);
            splats[k].geometry =
                splatGeometry(scene, plane, settings, voxel, extinctionOf(scene, settings, cls), mode, &c);
            splats[k].colour = glm::dvec3(scene.lut[cls]);
            splats[k].slice = glm::ivec3(glm::round((scene.positionOf(voxel) - scene.origin) / scene.spacing))[trav.axis];
        }
    });
    SplatCounters total;
    total.visible = n;
    perThread.combine_each([&](const SplatCounters& c) { addCounters(total, c); });
    if (counters) *counters = total;

    // 2. Composite bands of rows; each band walks all splats in order and touches only its rows.
    const int w = plane.width, h = plane.height;
    std::vector<double> acc(size_t(w) * h * 4, 0.0);
    const double cut2 = settings.cutoffSigmas * settings.cutoffSigmas;
    const Compositing mode = settings.compositing;
    const bool sheets = mode == Compositing::SheetBackToFront || mode == Compositing::SheetFrontToBack;
    const bool frontToBack = mode == Compositing::SheetFrontToBack;
    constexpr int kBand = 8;
    tbb::parallel_for(0, (h + kBand - 1) / kBand, [&](int band) {
        const int y0 = band * kBand, y1 = std::min(h, y0 + kBand);
        // Sheet buffer of this band: per pixel (sum c tau, sum tau) of the current slice.
        std::vector<double> sheet(sheets ? size_t(y1 - y0) * w * 4 : 0, 0.0);
        std::vector<double> transmittance(frontToBack ? size_t(y1 - y0) * w : 0, 1.0);
        auto flushSheet = [&] {
            for (int y = y0; y < y1; ++y)
                for (int x = 0; x < w; ++x) {
                    double* q = &sheet[(size_t(y - y0) * w + x) * 4];
                    if (q[3] > 0.0) {
                        const double a = -std::expm1(-q[3]);
                        const double c[3] = {q[0] / q[3] * a, q[1] / q[3] * a, q[2] / q[3] * a};
                        double* p = &acc[(size_t(y) * w + x) * 4];
                        if (frontToBack) {
                            double& t = transmittance[size_t(y - y0) * w + x];
                            for (int k = 0; k < 3; ++k) p[k] += t * c[k];
                            p[3] += t * a;
                            t *= 1.0 - a;
                        } else {
                            over(p, c, a);
                        }
                    }
                    q[0] = q[1] = q[2] = q[3] = 0.0;
                }
        };
        int currentSlice = INT32_MIN;
        for (size_t k = 0; k < n; ++k) {
            const Splat& s = splats[frontToBack ? n - 1 - k : k];
            if (sheets && s.slice != currentSlice) {
                if (currentSlice != INT32_MIN) flushSheet();
                currentSlice = s.slice;
            }
            const SplatGeometry& g = s.geometry;
            if (g.culled) continue;
            // Pixels whose centres (i + 0.5) fall inside the bounding box of the cutoff ellipse.
            const int ya = std::max(y0, int(std::ceil(g.centrePx.y - g.halfExtentPx.y - 0.5)));
            const int yb = std::min(y1 - 1, int(std::floor(g.centrePx.y + g.halfExtentPx.y - 0.5)));
            if (ya > yb) continue;
            const int xa = std::max(0, int(std::ceil(g.centrePx.x - g.halfExtentPx.x - 0.5)));
            const int xb = std::min(w - 1, int(std::floor(g.centrePx.x + g.halfExtentPx.x - 0.5)));
            for (int y = ya; y <= yb; ++y)
                for (int x = xa; x <= xb; ++x) {
                    const glm::dvec2 d = glm::dvec2(x + 0.5, y + 0.5) - g.centrePx;
                    const double e = glm::dot(d, g.conic * d);
                    if (e > cut2) continue;
                    const double tau = g.amplitude * std::exp(-0.5 * e);
                    double* p = sheets ? &sheet[(size_t(y - y0) * w + x) * 4] : &acc[(size_t(y) * w + x) * 4];
                    if (sheets || mode == Compositing::XRay) {
                        for (int c = 0; c < 3; ++c) p[c] += s.colour[c] * tau;
                        p[3] += tau;
                    } else {
                        const double a = -std::expm1(-tau);
                        const double c[3] = {s.colour[0] * a, s.colour[1] * a, s.colour[2] * a};
                        over(p, c, a);   // back to front, premultiplied
                    }
                }
        }
        if (sheets && currentSlice != INT32_MIN) flushSheet();
    });

    Image img(w, h);
    const bool xray = mode == Compositing::XRay;
    for (size_t i = 0; i < acc.size(); ++i)
        img.rgba[i] = float(xray ? -std::expm1(-acc[i]) : acc[i]);   // X-ray shows 1 - exp(-sum)
    return img;
}

} // namespace renderer
