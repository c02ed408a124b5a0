// One headless GL context for the whole gl suite. Without EGL the tests skip with the reason, unless
// REQUIRE_GL=1 (CI), where a skipped GL suite would be a silent failure.
#pragma once
#include "image_compare.h"
#include "renderer/gl/gl_context.h"
#include "renderer/oracle/reference_renderer.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

class GlTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (s_context || !s_failure.empty()) return;
        try {
            s_context = renderer::HeadlessGl::create();
        } catch (const std::exception& e) {
            s_failure = e.what();
        }
    }
    void SetUp() override {
        if (!s_failure.empty()) {
            const char* req = std::getenv("REQUIRE_GL");
            if (req && std::string(req) == "1") FAIL() << "REQUIRE_GL=1 but no GL context: " << s_failure;
            GTEST_SKIP() << "no headless GL context: " << s_failure;
        }
        renderer::takeGlErrors();
    }
    // Every GL test ends with KHR_debug silent.
    void TearDown() override {
        if (!s_context) return;
        const auto errors = renderer::takeGlErrors();
        EXPECT_TRUE(errors.empty()) << "KHR_debug reported: " << errors.front();
    }
    static inline std::unique_ptr<renderer::HeadlessGl> s_context;
    static inline std::string s_failure;
};

// GL against the CPU oracle: both composite the same splats in the same order; they differ only in
// float vs double arithmetic.
// Tolerance, per channel: abs 2e-5 + rel 2e-4. The vertex stage computes the footprint in float
// (relative error ~1e-6 per operation, ~30 operations), and blending ~100 layers in float adds ~1e-6
// absolute: measured on llvmpipe, mean |GL - CPU| 0.6e-7..5.4e-7 and max 1.2e-6..4.7e-6 away from
// cutoff edges. The exception is a pixel whose centre lies on a cutoff ellipse (e == cutoff^2 to
// ~1e-6): float and double may disagree on whether it is in, a jump of up to amplitude x
// exp(-cutoff^2/2), 1.1 % of that splat's peak (measured worst 1.4e-4). So 0.5 % of the pixels may
// fail, no channel may be off by more than 1e-2, and the mean must stay under 2e-6 (x4 the worst
// measured) so a slow drift cannot hide among the edge pixels.
inline const testing_support::Tolerance kGlVsCpu{
    .abs = 2e-5, .rel = 2e-4, .maxBadFraction = 0.005, .maxMeanAbs = 2e-6, .maxAbs = 1e-2};

// GPU counters against the CPU oracle's: every field equal.
inline void expectCountersEqual(const renderer::SplatCounters& gpu, const renderer::SplatCounters& cpu) {
    EXPECT_EQ(gpu.visible, cpu.visible);
    EXPECT_EQ(gpu.culledTransparent, cpu.culledTransparent);
    EXPECT_EQ(gpu.culledNear, cpu.culledNear);
    EXPECT_EQ(gpu.culledDegenerate, cpu.culledDegenerate);
    EXPECT_EQ(gpu.culledHuge, cpu.culledHuge);
    EXPECT_EQ(gpu.culledOffscreen, cpu.culledOffscreen);
    EXPECT_EQ(gpu.culledOccluded, cpu.culledOccluded);
    EXPECT_EQ(gpu.drawn, cpu.drawn);
    EXPECT_EQ(gpu.nearLayer, cpu.nearLayer);
    EXPECT_EQ(gpu.droppedNear, cpu.droppedNear);
    for (int m = 0; m < 3; ++m)
        EXPECT_EQ(gpu.drawnPerMode[m], cpu.drawnPerMode[m]) << renderer::filterModeName(renderer::FilterMode(m));
}
