// One voxel's footprint laid open, for the editor's footprint inspector (001 and 000 fig. 3): the
// projected reconstruction kernel, the low-pass filter and their sum, at the cutoff, with the filter
// the adaptive classifier gives the voxel's patch and the thresholds it measured against. CPU only.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/math/classifier.h"
#include "renderer/math/ewa.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <optional>

namespace renderer {

// An ellipse of a 2x2 variance at `sigmas` standard deviations: its semi-axes in pixels (major first) and
// the major axis' angle from the image's x axis (radians, y down as the image's rows).
struct Ellipse {
    glm::dvec2 semiAxesPx{0.0};
    double angleRad = 0.0;
};
Ellipse ellipseOf(const glm::dmat2& variancePx, double sigmas);

struct FootprintInspection {
    glm::ivec3 voxel{0};
    double depth = 0.0;                     // u2, object units
    glm::dvec2 centrePx{0.0};               // the projected kernel centre (x right, y down)
    double jacobianDet = 0.0;               // |J|: the footprint's integral over the image
    double cutoffSigmas = 3.0;
    glm::dmat2 reconstruction{1.0};         // V_hat: the projected kernel's variance, px^2
    glm::dmat2 lowPass{1.0};                // V_h: the low-pass filter's (sigma 1 px)
    glm::dmat2 ewa{1.0};                    // V_hat + V_h: the EWA footprint's
    FilterMode patchFilter = FilterMode::Ewa; // the filter the frame draws the voxel with (adaptive: its patch's)
    AdaptiveThresholds thresholds;          // what the adaptive classifier compares against
    glm::dvec2 kernelPx{0.0};               // R_k of the smallest and largest kernel sigma at this depth, px
    FilterDepths filterDepths;              // where the filter changes with depth (object units)
};

// The footprint of `voxel` in this view, or nothing where no splat is drawn for it (its kernel reaches the
// near plane). Uses the renderers' own formulas (projectKernel, classifyPatch); no hysteresis.
std::optional<FootprintInspection> inspectFootprint(const SplatScene& scene, const ImagePlane& plane,
                                                    const SplatSettings& settings, glm::ivec3 voxel);

} // namespace renderer
