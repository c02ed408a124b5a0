// The EWA footprint in pixel units (001 eq. 21-22, erratum of 000 eq. 3 applied): the one place the
// math lives. The CPU oracle calls it per splat; the GLSL vertex stage mirrors it line for line.
#pragma once
#include "renderer/math/glm_config.h"

#include <string>

namespace renderer {

// The three footprint filters, and Adaptive: per patch, whichever of the three the classifier picks
// (classifier.h). projectKernel takes only the first three.
enum class FilterMode { Reconstruction, LowPass, Ewa, Adaptive };
const char* filterModeName(FilterMode m);    // "reconstruction", "low-pass", "ewa", "adaptive"
FilterMode filterModeFromName(const std::string& name);   // throws RenderError listing the names

// Pixel-unit Jacobian of camera -> (pixel x, pixel y, ray distance) at camera point u (001 eq. 25
// with the first two rows scaled by fPx). Columns-major glm: J[col][row].
glm::dmat3 rayJacobianPx(glm::dvec3 u, double fPx);
// det J = fPx^2 |u| / u2^3, the voxel's projected area factor.
double rayJacobianDet(glm::dvec3 u, double fPx);

// Camera-space variance W diag(sigma^2) W^T of an axis-aligned kernel with per-axis sigma (object units).
glm::dmat3 kernelVarianceCamera(glm::dvec3 sigma, const glm::dmat3& viewFromObject);

struct Footprint {
    glm::dvec2 offsetPx{0.0};      // projected centre relative to the principal point
    glm::dmat2 variancePx{1.0};    // the filter's 2x2 variance (V_hat, V_h or V_hat + V_h)
    double jacobianDet = 0.0;      // |J|: the footprint integrates to this over the image
    double peak = 0.0;             // |J| / (2 pi sqrt(det variancePx)): the value at the centre
};

// Footprint of a unit-mass Gaussian with camera-space variance `varianceCamera` centred at `u`.
// lowPassPx is V_h (identity by default: sigma 1 px). Orthographic: the constant affine map
// diag(fPx, fPx, 1) replaces the Jacobian (fPx is then pixels per object unit).
Footprint projectKernel(glm::dvec3 u, const glm::dmat3& varianceCamera, double fPx, FilterMode mode,
                        const glm::dmat2& lowPassPx = glm::dmat2(1.0), bool orthographic = false);
// Kernels are cut off at `cutoffSigmas` and scaled back to unit mass, so that the splats and the ground
// truth integrate the same total (the audit found the 3D cut keeping 97.07 %, the 2D cut 98.89 %: the
// splats' optical depth 2.8-3.7 % above the truth's). A footprint, cut at its 2D ellipse, keeps
// 1 - exp(-c^2 / 2) of its mass; a kernel, cut at its 3D ellipsoid, keeps the chi-square(3) probability
// erf(c / sqrt 2) - sqrt(2 / pi) c exp(-c^2 / 2). Each divides its truncated Gaussian.
double footprintMassWithin(double cutoffSigmas);
double kernelMassWithin(double cutoffSigmas);

// q(p) = |J| G_V(p - centre) at an offset `d` from the projected centre.
double footprintAt(const Footprint& f, glm::dvec2 d);
// Squared Mahalanobis radius of offset d under the footprint's variance.
double footprintRadius2(const Footprint& f, glm::dvec2 d);

} // namespace renderer
