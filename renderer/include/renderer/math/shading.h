// Shading math both renderers share: per-voxel gradients packed into 3 bytes for the GPU (000 sec.
// 4.2), a two-sided headlight Phong model, and flattened surface-splat kernels (001 sec. 5) with the
// footprint floor that keeps them finite edge-on. Math only: no GL, no scene; shadingGlsl() mirrors it.
#pragma once
#include "renderer/model/gradients.h"

#include <cstdint>
#include <vector>

namespace renderer {

// == Packed gradients
// 24 bits a voxel, held in the low bits of a uint32 on the CPU and as 3 bytes a voxel on the GPU
// (gradientBufferBytes()); bytes in order (x is the low byte):
//   | u snorm8 | v snorm8 | sqrt(|g| / maxMagnitude) unorm8 |
// (u, v): the unit normal g/|g| in octahedral coordinates: p = n.xy / (|x| + |y| + |z|), folded
// (1 - |p.yx|) * sign(p.xy) where n.z < 0; q = round(127 p), decoded as max(q/127, -1). The normal
// is (u, v, 1 - |u| - |v|) unfolded where its z < 0 and normalised: within 0.96 degrees of g/|g|
// (0.90 measured; the three snorm8 components of the 4-byte format before were within 0.39: the byte
// saved keeps bonsai, engine and headsq under 8 GPU bytes a voxel with gradients, and their shaded
// images moved by 1/255 at most). w: q = round(255 sqrt(r)),
// r = |g| / maxMagnitude, decoded a = q/255 and r = a * a. The square root spends the 256 levels where
// shading decides (weak gradients: the no-normal fade, noise): r steps by 2 sqrt(r)/255, so r down to
// 1/65025 stays non-zero, where a linear byte zeroes everything below 1/510 of the (often outlier)
// maximum: over a quarter of headsq's voxels (p25 of |g| / max is 0.0013).
// A zero or non-finite gradient packs to 0; a magnitude byte of 0 decodes to the zero normal.
struct PackedGradients {
    std::vector<uint32_t> texels; // one per voxel, x fastest like Volume::values
    double maxMagnitude = 0.0;    // largest |g| in the field, data units per object unit
};
PackedGradients packGradients(const GradientField& field);
uint32_t packGradient(glm::dvec3 gradient, double maxMagnitude);
// Bytes the GPU holds for `voxels` packed gradients: 3 a voxel, whole words, and one word more so a
// voxel's 3 bytes can always be read as two words.
constexpr size_t gradientBufferBytes(size_t voxels) { return (3 * voxels + 3) / 4 * 4 + 4; }

// The magnitude byte as an index: gradient opacity is baked per byte value (splat_scene.h), so both
// renderers and the truth look one table up with the byte each voxel already has.
constexpr int kGradientBins = 256;
inline int magnitudeBin(uint32_t texel) { return int((texel >> 16) & 0xffu); }
// The magnitude a byte stands for, data units per object unit: maxMagnitude (bin / 255)^2.
inline double binMagnitude(int bin, double maxMagnitude) {
    const double a = bin / 255.0;
    return maxMagnitude * a * a;
}

// Voxels per magnitude byte (kGradientBins counts): the gradient opacity curve's histogram.
std::vector<uint64_t> magnitudeHistogram(const std::vector<uint32_t>& texels);

// What the GLSL unpackGradient() computes, in float, widened: the CPU oracle and GL shade the same
// normal (to float rounding: normalize() may round differently by an ulp or two).
struct DecodedGradient {
    glm::dvec3 normal{0.0}; // unit (to float rounding), or zero with a zero magnitude byte
    double magnitude = 0.0; // |g| / maxMagnitude in [0, 1], to the quantisation of the w byte
    // Relative gradient to hand to shade() (after W): the normal's direction, the magnitude's length.
    glm::dvec3 gradient() const { return normal * magnitude; }
};
DecodedGradient decodeGradient(uint32_t texel);

// == Headlight Phong
// White light at the eye, two-sided (|N.L|): volume gradients point either way across a surface.
struct ShadingParams {
    double ambient = 0.3;       // ambient + diffuse = 1: a face-on surface keeps its TF colour, as
    double diffuse = 0.7;       // does a voxel with no gradient (see flatGradient)
    double specular = 0.3;      // white highlight, added to the colour (may exceed 1)
    double shininess = 32.0;    // Phong exponent on R.V
    double flatGradient = 0.02; // |g| / maxMagnitude below which shading fades linearly to unshaded:
                                // homogeneous tissue and noise (headsq: median 0.005, p75 0.033),
                                // whose normals point anywhere, stays unshaded instead of speckled
};

// colour: TF colour (not premultiplied). gradientCamera: W times the decoded relative gradient
// (DecodedGradient::gradient(); W = ImagePlane::viewFromObject, a rotation, so it maps normals too).
// Its direction is the normal; its length r says how far to trust it: the result is
// mix(colour, phong, min(r / flatGradient, 1)), continuous in the gradient, and a zero gradient (no
// normal) gives the colour unshaded. toEyeCamera: from the shaded point to the eye, any length:
// per-vertex shading passes -u (the splat centre), per-fragment the pixel's ray reversed. Never NaN
// for finite inputs (zero vectors included).
glm::dvec3 shade(glm::dvec3 colour, glm::dvec3 gradientCamera, glm::dvec3 toEyeCamera,
                 const ShadingParams& params);
// Towards the eye along the ray through the pixel centre `px` (pixels, y down), in camera space: the
// view direction of per-fragment shading. centrePx and fPx are the image plane's.
glm::dvec3 toEyeAt(glm::dvec2 px, glm::dvec2 centrePx, double fPx, bool orthographic);

// == Surface splats (001 sec. 5)
// Camera-space variance of the kernel diag(sigma^2) scaled by 1/flatten along the unit object-space
// normal n: S = I - (1 - 1/flatten) n n^T, result W S diag(sigma^2) S^T W^T. This is 001's "scale the
// Gaussian in one direction by 1/s" for any sigma: variance along n shrinks by 1/flatten^2, every
// direction in the tangent plane keeps its variance, det by 1/flatten^2; flatten -> inf gives the
// tangent-plane disc P diag(sigma^2) P. The kernel stays a unit-mass Gaussian (projectKernel's |J|
// normaliser does not depend on the variance). flatten = 1 or a zero/non-finite normal returns
// kernelVarianceCamera(sigma, W) bit for bit. normalObject need not be unit (it is normalised here).
// flatten: >= 1, +inf allowed; anything else throws RenderError.
glm::dmat3 surfaceVarianceCamera(glm::dvec3 sigma, const glm::dmat3& viewFromObject, glm::dvec3 normalObject,
                                 double flatten);

// Smallest footprint variance (px^2, any direction) a splat drawn without the low-pass filter may
// have. Sampled at pixel centres, a 2D Gaussian of variance V sums to its integral times
// 1 + sum_{k != 0} exp(-2 pi^2 k^T V k) cos(...) (Poisson summation); with eigenvalues >= 0.3 the
// ripple is below 4 exp(-2 pi^2 0.3) = 1.1 % wherever the centre falls. Thinner edge-on splats fall
// between pixel rows (holes) or spike on them. V_h = I (EWA, low-pass) gives 1e-8 without a clamp.
constexpr double kMinFootprintVariancePx2 = 0.3;

// The 2x2 variance with every eigenvalue raised to at least minVariancePx2, eigenvectors kept:
// v + t (lambda_max I - v), t = (floor - lambda_min) / (lambda_max - lambda_min); floor I when both
// are below. Symmetric (uses the mean of the off-diagonals); returns v unchanged when lambda_min >=
// the floor. Raising an eigenvalue blurs, never changes the mass: the |J| normaliser stays.
// Non-finite input stays non-finite (the caller's degenerate-footprint cull catches it).
glm::dmat2 clampFootprintVariance(const glm::dmat2& v, double minVariancePx2 = kMinFootprintVariancePx2);

// == GLSL
// GLSL 4.50 source (no #version) of ShadingParams, toEyeAt(), shade() and the pieces of it the tiles'
// composite calls apart (unitOrZero, normalTrust, shadeUnit), surfaceVarianceCamera(),
// clampFootprintVariance() and unpackGradient(uint), line for line with the C++ above in float.
const char* shadingGlsl();

} // namespace renderer
