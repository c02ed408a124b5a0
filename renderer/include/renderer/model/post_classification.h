// Post-classification (issue 37; 000's and 002's future work): the TF applied to the reconstructed
// value, not to each voxel before reconstruction. A voxel's value is its class (a fractional class is
// a value between two classes' values), the reconstructed value at a point is the kernels' weighted mean
// sum v_k r_k / sum r_k, and the TF is the scene's LUT read between classes. The extinction of a point
// is the TF's opacity there times the kernels' weight sum_k r_k (1 inside the volume, fading to 0 over
// its border as the pre-classified kernels fade), times the density per mean spacing.
#pragma once
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

namespace renderer {

// The LUT at fractional class `value` (clamped to the LUT), linear between neighbouring classes.
glm::dvec4 lutAt(const Lut& lut, double value);

// Extinction per object unit at TF opacity 1: the settings' density per mean spacing, as voxelExtinction.
double extinctionPerOpacity(const SplatScene& scene, const SplatSettings& settings);

// Post-classification here takes a 1D TF on unshaded, volume kernels: throws RenderError naming `who`
// for gradient opacity, a 2D TF, shading or surface splats.
void requirePostClassifiable(const SplatScene& scene, const SplatSettings& settings, const std::string& who);

} // namespace renderer
