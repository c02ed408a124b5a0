// Levels of detail for far views (see detail_levels.h).
#include "renderer/model/detail_levels.h"

#include "renderer/math/classifier.h"
#include "renderer/model/gradients.h"

#include <array>
#include <cmath>
#include <limits>

namespace renderer {

double levelKernelPx(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing, const ImagePlane& plane,
                     const SplatSettings& s, int level) {
    const double nearest = plane.depthRange(dims, origin, spacing).x;
    if (!plane.orthographic && !(nearest > plane.nearDepth)) return std::numeric_limits<double>::infinity();
    return adaptiveThresholds(spacing, plane, s).sigmaMax * std::ldexp(1.0, level) * plane.pxPerUnit(nearest);
}

int coarsestLowPassLevel(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing, const ImagePlane& plane,
                         const SplatSettings& s, int maxLevel, int previous, double hysteresis) {
    const double threshold = adaptiveThresholds(spacing, plane, s).lowPassBelowPx;
    const double band = 1.0 + std::max(hysteresis, 0.0);
    int chosen = 0;
    // Each level's kernels are twice the last's: once one is too wide, every coarser one is.
    for (int k = 1; k <= maxLevel; ++k) {
        const double limit = k <= previous ? threshold * band : threshold / band;
        if (!(levelKernelPx(dims, origin, spacing, plane, s, k) < limit)) break;
        chosen = k;
    }
    return chosen;
}

namespace {

// Opacity times voxel volume, summed, then weighted by red, green and blue.
std::array<double, 4> opticalMass(const SplatScene& scene) {
    std::array<double, 4> mass{};
    const auto add = [&](double opacity, const glm::dvec3& colour, double voxels) {
        mass[0] += opacity * voxels;
        for (int c = 0; c < 3; ++c) mass[size_t(c + 1)] += opacity * colour[c] * voxels;
    };
    if (scene.tf2d.empty() && scene.gradientFactors.empty()) {   // one opacity a class: count by class
        for (size_t c = 0; c < scene.classVoxels.size() && c < scene.lut.size(); ++c)
            if (scene.classVoxels[c] > 0) add(scene.lut[c].a, glm::dvec3(scene.lut[c]), double(scene.classVoxels[c]));
    } else {
        for (uint32_t v = 0; v < uint32_t(scene.classes.size()); ++v)
            if (const double a = scene.opacityOf(v); a > 0.0) add(a, scene.colourOf(v), 1.0);
    }
    const double voxelVolume = scene.spacing.x * scene.spacing.y * scene.spacing.z;
    for (double& m : mass) m *= voxelVolume;
    return mass;
}

} // namespace

double opticalMassChange(const SplatScene& fine, const SplatScene& coarse) {
    const std::array<double, 4> f = opticalMass(fine), c = opticalMass(coarse);
    if (!(f[0] > 0.0)) return c[0] > 0.0 ? 1.0 : 0.0;
    // Each channel's change against the whole mass, not its own: a colour little of the scene emits (engine's
    // blue under `fire`, a tenth of its mass) changes by 13 % at level 1, 1.8 % of what is seen.
    double change = 0.0;
    for (size_t i = 0; i < f.size(); ++i) change = std::max(change, std::abs(c[i] - f[i]) / f[0]);
    return change;
}

DetailLevel chooseDetailLevel(const Volume& volume, const SplatScene& full, const ImagePlane& plane,
                              const SplatSettings& s, int maxLevel, int previous, double hysteresis) {
    DetailLevel d;
    d.pixelLevel = coarsestLowPassLevel(full.dims, full.origin, full.spacing, plane, s, maxLevel, previous, hysteresis);
    // The levels from finest to the one the pixels allow, each halved from the last; the first that changes
    // the optical mass too much ends the search, and the level before it is drawn.
    std::optional<Volume> kept;   // the last level kept: the next is halved from it (not a copy of `volume`)
    for (int k = 1; k <= d.pixelLevel; ++k) {
        Volume coarse = halfResolution(kept ? *kept : volume, Downsample::Mean);
        SplatScene scene = buildSplatScene(coarse, full.tf, full.window);
        if (!full.gradients.empty()) addGradients(scene, *computeGradients(coarse));
        const double change = opticalMassChange(full, scene);
        if (change > kMaxMassChange) {
            d.refusedMassChange = change;
            break;
        }
        d.level = k;
        d.massChange = change;
        d.densityScale = densityFor(coarse, volume, 1.0);
        d.scene = std::move(scene);
        kept = std::move(coarse);
    }
    d.kernelPx = levelKernelPx(full.dims, full.origin, full.spacing, plane, s, d.level);
    return d;
}

} // namespace renderer
