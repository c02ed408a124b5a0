// A kernel along a ray and its erf integral (see ray_kernel.h).
#include "renderer/oracle/ray_kernel.h"

#include "renderer/math/ewa.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace renderer {

double kernelPeak(glm::dvec3 spacing, glm::dvec3 sigma, double cutoffSigmas) {
    return (spacing.x * spacing.y * spacing.z) / (std::pow(2.0 * std::numbers::pi, 1.5) * sigma.x * sigma.y *
                                                  sigma.z * kernelMassWithin(cutoffSigmas));
}

std::optional<RayKernel> kernelAlongRay(glm::dvec3 origin, glm::dvec3 dir, glm::dvec3 centre,
                                        glm::dvec3 sigma, double cutoffSigmas, double peak) {
    // q(s) = (o + s d - t)^T S^-1 (o + s d - t) = a s^2 + 2 b s + c
    const glm::dvec3 inv2 = 1.0 / (sigma * sigma);
    const glm::dvec3 o = origin - centre;
    const double qa = glm::dot(dir * dir, inv2), qb = glm::dot(dir * o, inv2), qc = glm::dot(o * o, inv2);
    const double qMin = qc - qb * qb / qa;
    const double cut2 = cutoffSigmas * cutoffSigmas;
    if (!(qMin < cut2)) return std::nullopt;
    RayKernel k;
    k.mid = -qb / qa;
    k.width = 1.0 / std::sqrt(qa);
    k.halfLength = std::sqrt((cut2 - qMin) / qa);
    k.peak = peak * std::exp(-0.5 * qMin);
    k.extinction = 0.0;
    k.colour = glm::dvec3(0.0);
    return k;
}

double integrate(const RayKernel& k, double s0, double s1, ErfAt& last) {
    const double a = std::max(s0, k.mid - k.halfLength), b = std::min(s1, k.mid + k.halfLength);
    if (b <= a) return 0.0;
    const double scale = 1.0 / (std::numbers::sqrt2 * k.width);
    const double erfA = a == last.at ? last.value : std::erf((a - k.mid) * scale);
    last = {b, std::erf((b - k.mid) * scale)};
    return k.peak * k.width * std::sqrt(std::numbers::pi / 2.0) * (last.value - erfA);
}

} // namespace renderer
