#include "image_compare.h"

#include "test_paths.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <sstream>

namespace testing_support {

Comparison compareImages(const renderer::Image& a, const renderer::Image& e, const Tolerance& tol) {
    Comparison c;
    double sum = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            bool bad = false;
            for (int k = 0; k < 4; ++k) {
                const double av = a.pixel(x, y)[k], ev = e.pixel(x, y)[k];
                const double d = std::isfinite(av) ? std::abs(av - ev) : INFINITY;
                sum += d;
                if (d > tol.abs + tol.rel * std::abs(ev)) bad = true;
                if (d > c.maxAbs) c.maxAbs = d, c.worstX = x, c.worstY = y;
            }
            c.badPixels += bad;
        }
    c.meanAbs = sum / std::max<double>(1.0, double(a.rgba.size()));
    return c;
}

::testing::AssertionResult imagesClose(const renderer::Image& a, const renderer::Image& e, const Tolerance& tol,
                                       const std::string& name) {
    if (a.width != e.width || a.height != e.height)
        return ::testing::AssertionFailure() << name << ": sizes differ " << a.width << "x" << a.height << " vs "
                                             << e.width << "x" << e.height;
    const Comparison c = compareImages(a, e, tol);
    const double pixels = double(a.width) * a.height;
    const bool ok = double(c.badPixels) <= tol.maxBadFraction * pixels && c.meanAbs <= tol.maxMeanAbs &&
                    c.maxAbs <= tol.maxAbs;
    // Always printed: the measured margins are what a tolerance comment should quote.
    std::printf("[ compare  ] %s: %zu/%.0f pixels beyond tolerance, mean abs %.3g, max abs %.3g\n", name.c_str(),
                c.badPixels, pixels, c.meanAbs, c.maxAbs);
    if (ok) return ::testing::AssertionSuccess();

    // Evidence for a person: actual, expected and a diff amplified so 1e-3 is visible.
    const auto dir = testOutputDir();
    renderer::writeImage(a, dir / (name + "_actual.exr"));
    renderer::writeImage(e, dir / (name + "_expected.exr"));
    renderer::Image diff(a.width, a.height);
    for (size_t i = 0; i < diff.rgba.size(); ++i) diff.rgba[i] = std::min(1.0f, 100.0f * std::abs(a.rgba[i] - e.rgba[i]));
    for (size_t i = 3; i < diff.rgba.size(); i += 4) diff.rgba[i] = 1.0f;
    renderer::writeImage(diff, dir / (name + "_diff.png"));
    std::ostringstream msg;
    msg << name << ": " << c.badPixels << " of " << pixels << " pixels beyond abs " << tol.abs << " + rel "
        << tol.rel << " (allowed fraction " << tol.maxBadFraction << "); mean abs " << c.meanAbs << " (limit "
        << tol.maxMeanAbs << "); max abs " << c.maxAbs << " (limit " << tol.maxAbs << ") at (" << c.worstX << ", "
        << c.worstY << ")";
    if (c.worstX >= 0) {
        const float* pa = a.pixel(c.worstX, c.worstY);
        const float* pe = e.pixel(c.worstX, c.worstY);
        msg << " actual (" << pa[0] << ", " << pa[1] << ", " << pa[2] << ", " << pa[3] << ") expected (" << pe[0]
            << ", " << pe[1] << ", " << pe[2] << ", " << pe[3] << "); images in " << dir.string();
    }
    return ::testing::AssertionFailure() << msg.str();
}

RenderDifference renderDifference(const renderer::Image& a, const renderer::Image& b, float opaqueAlpha) {
    RenderDifference d;
    for (size_t p = 0; p + 3 < a.rgba.size() && p + 3 < b.rgba.size(); p += 4) {
        const bool opaque = std::min(a.rgba[p + 3], b.rgba[p + 3]) >= opaqueAlpha;
        float& worst = opaque ? d.atOpaque : d.elsewhere;
        for (size_t c = p; c < p + 4; ++c) worst = std::max(worst, std::abs(a.rgba[c] - b.rgba[c]));
    }
    return d;
}

} // namespace testing_support
