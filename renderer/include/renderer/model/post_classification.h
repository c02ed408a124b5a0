// Post-classification (issue 37; 000's and 002's future work): the TF applied to the reconstructed
// value, not to each voxel before reconstruction. A voxel's value is its class (a fractional class is
// a value between two classes' values), the reconstructed value at a point is the kernels' weighted mean
// sum v_k r_k / sum r_k, and the TF is the scene's LUT read between classes. The extinction of a point
// is the TF's opacity there times the kernels' weight sum_k r_k (1 inside the volume, fading to 0 over
// its border as the pre-classified kernels fade), times the density per mean spacing.
//
// Shaded, the normal is the kernels' weighted mean of their voxels' gradients (the decoded gradients
// both renderers shade pre-classified kernels with): sum g_k r_k / sum r_k, lit by shading.h's Phong
// from the point's own ray. A mean, not the analytic gradient of sum v_k r_k / sum r_k: the voxel
// gradients are what a GPU already holds (3 bytes a voxel), and where the voxels' gradients disagree (a
// thin sheet seen from both sides, noise) the mean is short and shading fades as it does for weak
// gradients. The sphere test (test_image_slabs.cpp) measures it against the analytic normal.
#pragma once
#include "renderer/math/shading.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

namespace renderer {

// The LUT at fractional class `value` (clamped to the LUT), linear between neighbouring classes.
glm::dvec4 lutAt(const Lut& lut, double value);

// Extinction per object unit at TF opacity 1: the settings' density per mean spacing, as voxelExtinction.
double extinctionPerOpacity(const SplatScene& scene, const SplatSettings& settings);

// What a stretch of ray (a ground-truth step, a slab at a pixel) gathers from the kernels: their weight
// (integrals over it), their values and, shaded, their camera-space relative gradients
// (DecodedGradient::gradient() rotated by viewFromObject), each times its weight.
struct PostSample {
    double weight = 0.0, valueSum = 0.0;
    glm::dvec3 gradientSum{0.0};
};

// Premultiplied RGBA of the stretch: the LUT at the mean value, alpha 1 - exp(-opacity perOpacity
// weight), lit with the mean gradient from toEyeCamera when `shading` is given. Zero for no weight.
glm::dvec4 classifyPost(const Lut& lut, double perOpacity, const PostSample& sample, const ShadingParams* shading,
                        glm::dvec3 toEyeCamera);

// Post-classification here takes a 1D TF on volume kernels: throws RenderError naming `who` for
// gradient opacity, a 2D TF or surface splats.
void requirePostClassifiable(const SplatScene& scene, const SplatSettings& settings, const std::string& who);

} // namespace renderer
