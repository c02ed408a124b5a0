// expectImagesClose: the one image comparison every test uses. Per pixel, a channel passes when
// |a - e| <= abs + rel |e|; a stated fraction of pixels may fail (silhouettes, where float and double
// disagree on which pixel centres fall inside a cutoff ellipse); the mean absolute error is bounded
// too, so slow drift is caught. On failure it writes actual, expected and an amplified diff.
#pragma once
#include "renderer/io/image.h"
#include "renderer/model/splat_settings.h"

#include <gtest/gtest.h>

#include <string>

namespace testing_support {

struct Tolerance {
    double abs = 1e-4;
    double rel = 1e-3;
    double maxBadFraction = 0.0;   // fraction of pixels allowed to exceed abs + rel
    double maxMeanAbs = 1e-5;      // mean |a - e| over all channels
    double maxAbs = 1.0;           // no channel may ever differ by more than this
};

struct Comparison {
    size_t badPixels = 0;
    double meanAbs = 0.0, maxAbs = 0.0;
    int worstX = -1, worstY = -1;
};

Comparison compareImages(const renderer::Image& actual, const renderer::Image& expected, const Tolerance& tol);

// gtest assertion: ::testing::AssertionResult so the message lands in the test log.
::testing::AssertionResult imagesClose(const renderer::Image& actual, const renderer::Image& expected,
                                       const Tolerance& tol, const std::string& name);

// Two renders of one view front to back: the largest channel difference at pixels under the
// early-termination opacity, and at pixels over it in both. Whether such a pixel's alpha has reached the
// threshold at a refresh can turn on the order of a tile's splats within a slice, which varies from run
// to run; one run then stops a refresh before the other, and the pixel differs by what it would still
// take: at most 1 - threshold.
struct RenderDifference {
    float elsewhere = 0.0f, atOpaque = 0.0f;
};
RenderDifference renderDifference(const renderer::Image& a, const renderer::Image& b,
                                  float opaqueAlpha = float(renderer::SplatSettings{}.opaqueAlpha));

} // namespace testing_support

#define EXPECT_IMAGES_CLOSE(actual, expected, tol, name) \
    EXPECT_TRUE(testing_support::imagesClose(actual, expected, tol, name))
