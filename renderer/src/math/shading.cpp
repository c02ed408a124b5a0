// Packed gradients, headlight Phong and surface-splat variances (see shading.h). The GLSL at the end
// mirrors shade(), surfaceVarianceCamera() and clampFootprintVariance() line for line, in float.
#include "renderer/math/shading.h"

#include "renderer/errors.h"
#include "renderer/math/ewa.h"
#include "gl/shader_sources.h"   // the GLSL twin of this file, renderer/shaders/shading.glsl

#include <algorithm>
#include <cmath>
#include <string>

namespace renderer {

uint32_t packGradient(glm::dvec3 gradient, double maxMagnitude) {
    const double len = glm::length(gradient);
    if (!(len > 0.0) || !std::isfinite(len) || !(maxMagnitude > 0.0)) return 0u;
    const glm::dvec3 n = gradient / len;
    // Octahedral: onto |x| + |y| + |z| = 1, the lower half folded over the upper's corners.
    const double l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    double u = n.x / l1, v = n.y / l1;
    if (n.z < 0.0) {
        const double fu = (1.0 - std::abs(v)) * (u >= 0.0 ? 1.0 : -1.0);
        v = (1.0 - std::abs(u)) * (v >= 0.0 ? 1.0 : -1.0);
        u = fu;
    }
    // |u|, |v| <= 1, so the rounded values already lie in [-127, 127] and [0, 255].
    const auto snorm = [](double x) { return uint32_t(uint8_t(int8_t(std::lround(127.0 * x)))); };
    const double r = std::min(len / maxMagnitude, 1.0);
    const uint32_t w = uint32_t(std::lround(255.0 * std::sqrt(r)));
    return w == 0 ? 0u : snorm(u) | snorm(v) << 8 | w << 16;
}

PackedGradients packGradients(const GradientField& field) {
    PackedGradients p;
    const size_t count = field.xyz.size() / 3;
    for (size_t i = 0; i < count; ++i)
        p.maxMagnitude = std::max(p.maxMagnitude, field.magnitude(i));
    p.texels.resize(count);
    for (size_t i = 0; i < count; ++i)
        p.texels[i] = packGradient(field.at(i), p.maxMagnitude);
    return p;
}

std::vector<uint64_t> magnitudeHistogram(const std::vector<uint32_t>& texels) {
    std::vector<uint64_t> counts(kGradientBins, 0);
    for (uint32_t t : texels) ++counts[size_t(magnitudeBin(t))];
    return counts;
}

DecodedGradient decodeGradient(uint32_t texel) {
    // unpackGradient() in GLSL, step for step in float: snorm c -> max(c / 127, -1) (GL 4.5 eq. 2.2),
    // unorm c -> c / 255 (eq. 2.1); float division is correctly rounded.
    const auto snorm = [&](int shift) { return std::max(float(int8_t(texel >> shift)) / 127.0f, -1.0f); };
    const float a = float((texel >> 16) & 0xffu) / 255.0f;
    float x = snorm(0), y = snorm(8);
    const float z = 1.0f - std::abs(x) - std::abs(y), t = std::max(-z, 0.0f);
    x += x >= 0.0f ? -t : t;
    y += y >= 0.0f ? -t : t;
    const float len = std::sqrt(x * x + y * y + z * z);
    DecodedGradient d;
    if (a > 0.0f) d.normal = glm::dvec3(double(x / len), double(y / len), double(z / len));
    d.magnitude = double(a * a); // GLSL's a * a, also rounded to float
    return d;
}

glm::dvec3 toEyeAt(glm::dvec2 px, glm::dvec2 centrePx, double fPx, bool orthographic) {
    return orthographic ? glm::dvec3(0.0, 0.0, -1.0) : -glm::dvec3((px - centrePx) / fPx, 1.0);
}

namespace {

glm::dvec3 unitOrZero(glm::dvec3 v) {
    const double l = glm::length(v);
    return l > 0.0 ? v / l : glm::dvec3(0.0);
}

// Trust in the normal: 0 without a gradient, 1 from flatGradient up; linear, so continuous.
double normalTrust(glm::dvec3 gradientCamera, const ShadingParams& params) {
    const double r = glm::length(gradientCamera);
    return r > 0.0 ? std::min(r / params.flatGradient, 1.0) : 0.0;
}

glm::dvec3 shadeUnit(glm::dvec3 colour, glm::dvec3 n, double trust, glm::dvec3 v, const ShadingParams& params) {
    // Headlight: L = V, so |N.L| = |N.V| and R.V = 2 (N.V)^2 - 1 (R = 2 (N.L) N - L).
    const double c = std::abs(glm::dot(n, v));
    const double rv = std::max(2.0 * c * c - 1.0, 0.0);
    const glm::dvec3 phong = colour * (params.ambient + params.diffuse * c) +
                             glm::dvec3(params.specular * std::pow(rv, params.shininess));
    // Fade to the unshaded colour where the normal is not to be trusted.
    return colour + trust * (phong - colour);
}

} // namespace

glm::dvec3 shade(glm::dvec3 colour, glm::dvec3 gradientCamera, glm::dvec3 toEyeCamera,
                 const ShadingParams& params) {
    return shadeUnit(colour, unitOrZero(gradientCamera), normalTrust(gradientCamera, params),
                     unitOrZero(toEyeCamera), params);
}

glm::dmat3 surfaceVarianceCamera(glm::dvec3 sigma, const glm::dmat3& viewFromObject, glm::dvec3 normalObject,
                                 double flatten) {
    if (!(flatten >= 1.0))
        throw RenderError("surface splat flatten factor " + std::to_string(flatten) +
                          ": expected >= 1 (1: volume kernel, inf: disc)");
    const double len = glm::length(normalObject);
    const glm::dvec3 n = len > 0.0 && !std::isinf(len) ? normalObject / len : glm::dvec3(0.0);
    // S scales by 1/flatten along n and keeps the tangent plane; S = I exactly for flatten 1 or n = 0.
    const glm::dmat3 s = glm::dmat3(1.0) - (1.0 - 1.0 / flatten) * glm::outerProduct(n, n);
    // W S diag(sigma^2) S^T W^T: the flattened kernel is the volume kernel seen through the map W S.
    return kernelVarianceCamera(sigma, viewFromObject * s);
}

glm::dmat2 clampFootprintVariance(const glm::dmat2& v, double minVariancePx2) {
    // Eigenvalues m -+ d of the symmetrised matrix.
    const double a = v[0][0], c = v[1][1], b = 0.5 * (v[0][1] + v[1][0]);
    const double m = 0.5 * (a + c), h = 0.5 * (a - c);
    const double d = std::sqrt(h * h + b * b);
    const double lo = m - d, hi = m + d;
    if (lo >= minVariancePx2) return v;
    if (hi <= minVariancePx2) return glm::dmat2(minVariancePx2);
    // (hi I - s) / (hi - lo) projects onto lo's eigenvector, so this moves lo to the floor alone.
    const double t = (minVariancePx2 - lo) / (hi - lo);
    const glm::dmat2 s(a, b, b, c);
    return s + t * (hi * glm::dmat2(1.0) - s);
}

// The GLSL lives in renderer/shaders/shading.glsl, embedded at build time beside the renderer's shaders.
const char* shadingGlsl() { return shaderSource("shading.glsl"); }

} // namespace renderer
