// The TF read between classes (see post_classification.h).
#include "renderer/model/post_classification.h"

#include "renderer/errors.h"

#include <algorithm>
#include <cmath>

namespace renderer {

glm::dvec4 lutAt(const Lut& lut, double value) {
    const double v = std::clamp(std::isnan(value) ? 0.0 : value, 0.0, double(lut.size() - 1));
    const size_t i = std::min(size_t(v), lut.size() - 2);
    const double t = v - double(i);
    return glm::dvec4(lut[i]) * (1.0 - t) + glm::dvec4(lut[i + 1]) * t;
}

glm::dvec4 classifyPost(const Lut& lut, double perOpacity, const PostSample& sample, const ShadingParams* shading,
                        glm::dvec3 toEyeCamera) {
    if (!(sample.weight > 0.0)) return glm::dvec4(0.0);
    const glm::dvec4 tf = lutAt(lut, sample.valueSum / sample.weight);
    const double a = -std::expm1(-tf.a * perOpacity * sample.weight);
    glm::dvec3 colour(tf);
    if (shading) colour = shade(colour, sample.gradientSum / sample.weight, toEyeCamera, *shading);
    return glm::dvec4(colour * a, a);
}

double extinctionPerOpacity(const SplatScene& scene, const SplatSettings& settings) {
    return settings.density / ((scene.spacing.x + scene.spacing.y + scene.spacing.z) / 3.0);
}

void requirePostClassifiable(const SplatScene& scene, const SplatSettings& settings, const std::string& who) {
    const char* what = !scene.gradientFactors.empty()                   ? "gradient opacity"
                       : !scene.tf2d.empty()                            ? "a 2D transfer function"
                       : settings.surfaceFlatten > 1.0                  ? "surface splats"
                                                                        : nullptr;
    if (what)
        throw RenderError(who + ": post-classification takes a 1D transfer function on volume kernels, not " + what);
}

} // namespace renderer
