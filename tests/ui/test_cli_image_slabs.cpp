// `splatlab render --image-slabs T`: image-aligned slabs with GL or on the CPU oracle, for one image or an orbit;
// a smooth ball looks as the object-aligned sheets draw it, post-classified and shaded it follows its own
// truth, and what the slabs cannot do is refused.
#include "cli_run.h"

#include "renderer/io/image.h"
#include "renderer/math/metrics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

using testing::HasSubstr;
using testing_support::CliRun;
using testing_support::splatlab;

namespace {

// A float ball 16 voxels across, densest at its centre (dims in the file name).
std::string ballRaw() {
    const auto path = testing_support::testOutputDir() / "slab_ball_16x16x16_float32.raw";
    std::vector<float> values(16 * 16 * 16);
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const double r2 = ((x - 7.5) * (x - 7.5) + (y - 7.5) * (y - 7.5) + (z - 7.5) * (z - 7.5)) / 49.0;
                values[size_t((z * 16 + y) * 16 + x)] = float(std::max(0.0, 1.0 - r2));
            }
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(values.data()),
                                                std::streamsize(values.size() * sizeof(float)));
    return path.string();
}

CliRun render(const std::string& out, const std::string& flags) {
    return splatlab("render \"" + ballRaw() + "\" --tf grey-ramp --size 48x48 --frames 1 --out \"" + out + "\" " + flags);
}

} // namespace

TEST(CliImageSlabs, DrawsTheBallAsTheSheetsDoAndCountsTheSlabs) {
    const std::string dir = testing_support::testOutputDir().string();
    const CliRun slabs = render(dir + "/ball_slabs.exr", "--image-slabs 0.5 --counters");
    ASSERT_EQ(slabs.status, 0) << slabs.output;
    EXPECT_THAT(slabs.output, HasSubstr("image-aligned slabs 0.5 voxels thick"));
    EXPECT_THAT(slabs.output, testing::Not(HasSubstr("CPU oracle"))) << "without --cpu the pixels go to GL";
    EXPECT_THAT(slabs.output, HasSubstr("footprint pixels written"));
    const CliRun oracle = render(dir + "/ball_slabs_cpu.exr", "--image-slabs 0.5 --cpu");
    ASSERT_EQ(oracle.status, 0) << oracle.output;
    EXPECT_THAT(oracle.output, HasSubstr("on CPU oracle (double)"));
    const CliRun sheets = render(dir + "/ball_sheets.exr", "--cpu --compositing sheet-front-to-back");
    ASSERT_EQ(sheets.status, 0) << sheets.output;
    const renderer::Image a = renderer::readImage(dir + "/ball_slabs.exr"), b = renderer::readImage(dir + "/ball_sheets.exr");
    ASSERT_TRUE(renderer::imageStats(a).finite);
    EXPECT_GT(renderer::imageStats(a).maxAlpha, 0.3) << "the ball must be drawn";
    // A smooth ball: slices and slabs cut it differently but add up to the same (measured 0.0022).
    EXPECT_LT(renderer::compareImages(a, b).rmse, 0.01);
    EXPECT_LT(renderer::compareImages(a, renderer::readImage(dir + "/ball_slabs_cpu.exr")).maxAbs, 1e-4)
        << "GL and the oracle draw the same slabs";
}

TEST(CliImageSlabs, TurnsAnOrbit) {
    const std::string dir = testing_support::testOutputDir().string();
    const CliRun orbit = render(dir + "/ball_orbit.png", "--image-slabs 1 --orbit 90");
    ASSERT_EQ(orbit.status, 0) << orbit.output;
    EXPECT_THAT(orbit.output, HasSubstr("4 frames, 90 deg apart"));
    EXPECT_THAT(orbit.output, HasSubstr("image-aligned slabs 1 voxels thick on "));
}

TEST(CliImageSlabs, RefusesAThicknessOrAHeatmapItCannotDraw) {
    const std::string dir = testing_support::testOutputDir().string();
    const CliRun thin = render(dir + "/ball_thin.png", "--image-slabs 0.01");
    EXPECT_NE(thin.status, 0);
    EXPECT_THAT(thin.output, HasSubstr("--image-slabs: expected a slab thickness of 0.05 to 64 voxels"));
    const CliRun heat = render(dir + "/ball_heat.png", "--image-slabs 0.5 --heatmap \"" + dir + "/heat.png\"");
    EXPECT_NE(heat.status, 0);
    EXPECT_THAT(heat.output, HasSubstr("the image-aligned slabs draw no heatmap"));
    const CliRun xray = render(dir + "/ball_xray.png", "--image-slabs 0.5 --compositing xray");
    EXPECT_NE(xray.status, 0);
    EXPECT_THAT(xray.output, HasSubstr("X-ray compositing has no order to slice"));
}

// Post-classified, shaded and resolved from 2x2 samples a pixel: the slabs follow the post-classified
// shaded truth `reference --post-classified` computes (measured 56 dB), where the pre-classified
// object-aligned sheets do not.
TEST(CliImageSlabs, PostClassifiedShadedSlabsFollowTheirTruth) {
    const std::string dir = testing_support::testOutputDir().string();
    const std::string shaded = "--shading per-fragment";   // the truth has no filter to choose
    const CliRun post = render(dir + "/ball_post.exr",
                               "--image-slabs 0.25 --post-classify --supersample 2 --filter reconstruction " + shaded);
    ASSERT_EQ(post.status, 0) << post.output;
    EXPECT_THAT(post.output, HasSubstr("image-aligned slabs 0.25 voxels thick, post-classified, 2x2 samples a pixel"));
    const CliRun truth = splatlab("reference \"" + ballRaw() + "\" --tf grey-ramp --size 48x48 --post-classified " + shaded +
                                  " --no-cache --out \"" + dir + "/ball_post_truth.exr\"");
    ASSERT_EQ(truth.status, 0) << truth.output;
    const CliRun sheets = render(dir + "/ball_pre.exr", "--cpu " + shaded);
    ASSERT_EQ(sheets.status, 0) << sheets.output;
    const renderer::Image t = renderer::readImage(dir + "/ball_post_truth.exr");
    const double own = renderer::compareImages(renderer::readImage(dir + "/ball_post.exr"), t).psnrDb;
    const double pre = renderer::compareImages(renderer::readImage(dir + "/ball_pre.exr"), t).psnrDb;
    std::printf("[ cli slabs ] ball, post-classified shaded: slabs %.2f dB, pre-classified sheets %.2f dB against the "
                "post-classified truth\n", own, pre);
    EXPECT_GT(own, 40.0);
    EXPECT_GT(own, pre + 10.0);
    const CliRun alone = render(dir + "/ball_ss.png", "--supersample 2");
    EXPECT_NE(alone.status, 0);
    EXPECT_THAT(alone.output, HasSubstr("--supersample: applies to image-aligned slabs: give --image-slabs THICKNESS"));
    const CliRun many = render(dir + "/ball_ss5.png", "--image-slabs 0.5 --supersample 5");
    EXPECT_NE(many.status, 0);
    EXPECT_THAT(many.output, HasSubstr("supersample must be 0..4, got 5"));
}
