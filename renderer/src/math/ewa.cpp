// EWA footprint math in double precision (see ewa.h). Erratum: 000 eq. (3) misprints row 2 of the
// Jacobian; we use 001 eq. (25), whose determinant is |u| / u2^3 (times fPx^2 in pixel units).
#include "renderer/math/ewa.h"

#include "renderer/model/enum_names.h"
#include "renderer/errors.h"

#include <cassert>

#include <cmath>
#include <numbers>

namespace renderer {

const char* filterModeName(FilterMode m) {
    switch (m) {
    case FilterMode::Reconstruction: return "reconstruction";
    case FilterMode::LowPass: return "low-pass";
    case FilterMode::Ewa: return "ewa";
    case FilterMode::Adaptive: return "adaptive";
    }
    return "?";
}

FilterMode filterModeFromName(const std::string& name) {
    return enumFromName(name, {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa, FilterMode::Adaptive},
                        &filterModeName, "filter");
}

glm::dmat3 rayJacobianPx(glm::dvec3 u, double fPx) {
    const double l = glm::length(u);
    const double inv = 1.0 / u.z;
    // Rows: (f/u2, 0, -f u0/u2^2), (0, f/u2, -f u1/u2^2), (u0/l, u1/l, u2/l). glm is column-major.
    return glm::transpose(glm::dmat3(fPx * inv, 0.0, -fPx * u.x * inv * inv,   //
                                     0.0, fPx * inv, -fPx * u.y * inv * inv,   //
                                     u.x / l, u.y / l, u.z / l));
}

glm::dmat3 kernelVarianceCamera(glm::dvec3 sigma, const glm::dmat3& w) {
    const glm::dvec3 v = sigma * sigma;
    return w * glm::dmat3(glm::dvec3(v.x, 0, 0), glm::dvec3(0, v.y, 0), glm::dvec3(0, 0, v.z)) * glm::transpose(w);
}

double rayJacobianDet(glm::dvec3 u, double fPx) { return fPx * fPx * glm::length(u) / (u.z * u.z * u.z); }

Footprint projectKernel(glm::dvec3 u, const glm::dmat3& varianceCamera, double fPx, FilterMode mode,
                        const glm::dmat2& lowPassPx, bool orthographic) {
    assert(mode != FilterMode::Adaptive && "resolve Adaptive with the classifier first");
    const glm::dmat3 j = orthographic ? glm::dmat3(glm::dvec3(fPx, 0, 0), glm::dvec3(0, fPx, 0), glm::dvec3(0, 0, 1))
                                      : rayJacobianPx(u, fPx);
    const glm::dmat3 v = j * varianceCamera * glm::transpose(j);
    const glm::dmat2 vHat(v[0][0], v[0][1], v[1][0], v[1][1]);

    Footprint f;
    f.offsetPx = orthographic ? fPx * glm::dvec2(u.x, u.y) : fPx * glm::dvec2(u.x / u.z, u.y / u.z);
    f.jacobianDet = orthographic ? fPx * fPx : rayJacobianDet(u, fPx);
    switch (mode) {
    case FilterMode::Reconstruction: f.variancePx = vHat; break;
    case FilterMode::LowPass: f.variancePx = lowPassPx; break;
    case FilterMode::Ewa:
    case FilterMode::Adaptive: f.variancePx = vHat + lowPassPx; break;
    }
    // The |J| normaliser stays in every mode, so each deposits the same total and modes can mix.
    f.peak = f.jacobianDet / (2.0 * std::numbers::pi * std::sqrt(glm::determinant(f.variancePx)));
    return f;
}

double footprintMassWithin(double cutoffSigmas) { return -std::expm1(-0.5 * cutoffSigmas * cutoffSigmas); }

double kernelMassWithin(double cutoffSigmas) {
    const double c = cutoffSigmas;
    return std::erf(c / std::numbers::sqrt2) - std::sqrt(2.0 / std::numbers::pi) * c * std::exp(-0.5 * c * c);
}

double footprintRadius2(const Footprint& f, glm::dvec2 d) { return glm::dot(d, glm::inverse(f.variancePx) * d); }

double footprintAt(const Footprint& f, glm::dvec2 d) { return f.peak * std::exp(-0.5 * footprintRadius2(f, d)); }

} // namespace renderer
