// The CPU oracle (see reference_renderer.h). Two phases: (1) every splat's geometry, in parallel;
// (2) compositing in draw order, parallel over bands of rows, so each pixel sees the splats in exactly
// the order the GL path blends them and the result does not depend on the thread count.
#include "renderer/reference_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace renderer {

double extinctionOf(const SplatScene& scene, const SplatSettings& settings, uint16_t cls) {
    const double meanSpacing = (scene.spacing.x + scene.spacing.y + scene.spacing.z) / 3.0;
    return double(scene.lut[cls].a) * settings.density / meanSpacing;
}

static glm::dmat3 objectVariance(const SplatScene& scene, const SplatSettings& settings) {
    const glm::dvec3 sigma = settings.kernelScale * scene.spacing;
    return glm::dmat3(glm::dvec3(sigma.x * sigma.x, 0, 0), glm::dvec3(0, sigma.y * sigma.y, 0),
                      glm::dvec3(0, 0, sigma.z * sigma.z));
}

SplatGeometry splatGeometry(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                            uint32_t voxel, double extinction, SplatCounters* counters) {
    SplatGeometry g;
    g.culled = true;
    const glm::dvec3 u = plane.toCamera(scene.positionOf(voxel));
    if (!(u.z > plane.nearDepth)) {
        if (counters) ++counters->culledNear;
        return g;
    }
    const glm::dmat3 w = plane.viewFromObject;
    const glm::dmat3 varCamera = w * objectVariance(scene, settings) * glm::transpose(w);
    const Footprint f = projectKernel(u, varCamera, plane.fPx, settings.filter);
    const double det = glm::determinant(f.variancePx);
    if (!(det > 1e-12)) {
        if (counters) ++counters->culledDegenerate;
        return g;
    }
    g.centrePx = plane.centrePx + f.offsetPx;
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
    if (counters) ++counters->drawn;
    return g;
}

namespace {

struct Splat {
    SplatGeometry geometry;
    glm::dvec3 colour;
};

void addCounters(SplatCounters& a, const SplatCounters& b) {
    a.drawn += b.drawn;
    a.culledNear += b.culledNear;
    a.culledOffscreen += b.culledOffscreen;
    a.culledHuge += b.culledHuge;
    a.culledDegenerate += b.culledDegenerate;
}

} // namespace

Image renderReference(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                      SplatCounters* counters) {
    const Traversal trav = chooseTraversal(plane);
    const auto& list = scene.visible[trav.axis];
    const size_t n = list.size();

    // 1. Geometry of every splat, in draw order (back to front for splat-every-sample).
    std::vector<Splat> splats(n);
    tbb::combinable<SplatCounters> perThread;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
        auto& c = perThread.local();
        for (size_t k = r.begin(); k != r.end(); ++k) {
            const uint32_t voxel = list[trav.descending ? n - 1 - k : k];
            const uint16_t cls = scene.classes[voxel];
            splats[k].geometry = splatGeometry(scene, plane, settings, voxel, extinctionOf(scene, settings, cls), &c);
            splats[k].colour = glm::dvec3(scene.lut[cls]);
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
    const bool xray = settings.compositing == Compositing::XRay;
    constexpr int kBand = 8;
    tbb::parallel_for(0, (h + kBand - 1) / kBand, [&](int band) {
        const int y0 = band * kBand, y1 = std::min(h, y0 + kBand);
        for (const Splat& s : splats) {
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
                    double* p = &acc[(size_t(y) * w + x) * 4];
                    if (xray) {
                        for (int c = 0; c < 3; ++c) p[c] += s.colour[c] * tau;
                        p[3] += tau;
                    } else {
                        // Back-to-front "over" with premultiplied colour c a.
                        const double a = -std::expm1(-tau);
                        for (int c = 0; c < 3; ++c) p[c] = s.colour[c] * a + (1.0 - a) * p[c];
                        p[3] = a + (1.0 - a) * p[3];
                    }
                }
        }
    });

    Image img(w, h);
    for (size_t i = 0; i < acc.size(); ++i)
        img.rgba[i] = float(xray ? -std::expm1(-acc[i]) : acc[i]);   // X-ray shows 1 - exp(-sum)
    return img;
}

} // namespace renderer
