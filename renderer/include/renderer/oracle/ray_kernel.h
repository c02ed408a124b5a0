// One truncated 3D Gaussian kernel seen along one ray: a 1D Gaussian on an interval, and its closed-form
// (erf) integral over a stretch of the ray. The ground truth (ground_truth.h) marches these; the near
// layer (near_layer.h) integrates the kernels at the near plane with them. Double precision, CPU only.
#pragma once
#include "renderer/math/glm_config.h"

#include <limits>
#include <optional>

namespace renderer {

// r(s) = peak exp(-(s - mid)^2 / (2 width^2)) for |s - mid| <= halfLength, s the ray parameter (object
// units).
struct RayKernel {
    double mid, width, halfLength, peak;
    double extinction; // g_k
    glm::dvec3 colour;
    double value = 0.0; // post-classification: the voxel's class (post_classification.h)
    glm::dvec3 gradient{0.0}; // post-classified shading: the voxel's relative gradient, camera space
};

// Peak of a kernel r_k = voxel volume x unit-mass Gaussian, so that the kernels sum to ~1 over the grid;
// cut at the cutoff ellipsoid, each is scaled back to unit mass (kernelMassWithin, ewa.h), as the
// splats' footprints are.
double kernelPeak(glm::dvec3 spacing, glm::dvec3 sigma, double cutoffSigmas);

// The kernel centred at `centre` with axis-aligned `sigma` (object units), cut at `cutoffSigmas` and of
// peak value `peak` at its centre, along the ray origin + s dir (dir of unit length); nothing when the
// ray misses its cutoff ellipsoid. Extinction and colour are left for the caller.
std::optional<RayKernel> kernelAlongRay(glm::dvec3 origin, glm::dvec3 dir, glm::dvec3 centre,
                                        glm::dvec3 sigma, double cutoffSigmas, double peak);

// The erf a kernel's previous stretch took at its end, where the next one starts: a march takes each
// erf once, not twice (erf was a third of a ground truth's time).
struct ErfAt {
    double at = std::numeric_limits<double>::quiet_NaN(), value = 0.0;
};
// Closed-form integral of `k` over [s0, s1] (0 outside its interval).
double integrate(const RayKernel& k, double s0, double s1, ErfAt& last);
inline double integrate(const RayKernel& k, double s0, double s1) {
    ErfAt none;
    return integrate(k, s0, s1, none);
}

} // namespace renderer
