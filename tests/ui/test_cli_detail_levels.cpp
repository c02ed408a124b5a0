// `splatlab render --detail-levels N`: a far view drawn from a coarser level where its kernels stay
// under the low-pass threshold and it keeps the optical mass, said on stderr; near views and thin
// features stay at full resolution.
#include "cli_run.h"

#include "renderer/io/image.h"
#include "renderer/math/metrics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>

using testing::HasSubstr;
using testing_support::CliRun;
using testing_support::splatlab;

namespace {

// A uint8 ball 32 voxels across whose value falls smoothly to 0 at its edge (dims in the file name).
std::string smoothBallRaw() {
    const auto path = testing_support::testOutputDir() / "ball_32x32x32_uint8.raw";
    std::string bytes(32 * 32 * 32, '\0');
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                const double r2 = ((x - 15.5) * (x - 15.5) + (y - 15.5) * (y - 15.5) + (z - 15.5) * (z - 15.5)) / (14.0 * 14.0);
                bytes[size_t((z * 32 + y) * 32 + x)] = char(std::lround(255.0 * std::max(0.0, 1.0 - r2)));
            }
    std::ofstream(path, std::ios::binary) << bytes;
    return path.string();
}

CliRun renderBall(const std::string& out, const std::string& flags) {
    return splatlab("render \"" + smoothBallRaw() + "\" --tf grey-ramp --size 64x64 --frames 1 --out \"" + out + "\" " +
                    flags);
}

} // namespace

TEST(CliDetailLevels, AFarViewDrawsAHalvedVolumeCloseToTheFullOne) {
    const std::string dir = testing_support::testOutputDir().string();
    const CliRun full = renderBall(dir + "/ball_full.exr", "--camera 30,20,40,30");
    ASSERT_EQ(full.status, 0) << full.output;
    const CliRun coarse = renderBall(dir + "/ball_level.exr", "--camera 30,20,40,30 --detail-levels 2");
    ASSERT_EQ(coarse.status, 0) << coarse.output;
    // At 40 radii level 2's kernels are 0.31 px, under 0.44 (the low-pass threshold at 64x64, fov 30), but
    // 8 voxels across the ball change its optical mass by 4 %: level 1 is drawn.
    EXPECT_THAT(coarse.output, HasSubstr("note: level 2 would change the optical mass by 4.0 %"));
    EXPECT_THAT(coarse.output, HasSubstr("level 1 (16 x 16 x 16 voxels): kernels of 0.16 px at the nearest voxel, "
                                         "under the low-pass threshold 0.44 px"));
    const auto splats = [](const std::string& output) {
        std::smatch m;
        return std::regex_search(output, m, std::regex("([0-9]+) splats")) ? std::stod(m[1]) : 0.0;
    };
    EXPECT_NEAR(splats(full.output) / splats(coarse.output), 8.0, 1.0) << "an eighth of the voxels";
    const double rmse = renderer::compareImages(renderer::readImage(dir + "/ball_level.exr"),
                                                renderer::readImage(dir + "/ball_full.exr")).rmse;
    EXPECT_LT(rmse, 0.002);   // measured 0.00019
    EXPECT_GT(rmse, 0.0) << "another scene was drawn";
}

TEST(CliDetailLevels, NearViewsAndThinFeaturesStayAtFullResolution) {
    const std::string out = (testing_support::testOutputDir() / "detail_near.png").string();
    const CliRun nearView = renderBall(out, "--camera 30,20,2.5,30 --detail-levels 2");
    ASSERT_EQ(nearView.status, 0) << nearView.output;
    EXPECT_THAT(nearView.output, HasSubstr("note: full resolution: kernels of"));
    // headsq's one-voxel skin under ct-skin-bone: its mean with air leaves the TF's band.
    const CliRun skin = splatlab("render \"" + testing_support::headsq() + "\" --up -z --size 64x64 --frames 1 "
                                 "--camera 30,20,60,30 --detail-levels 1 --out \"" + out + "\"");
    ASSERT_EQ(skin.status, 0) << skin.output;
    EXPECT_THAT(skin.output, HasSubstr("note: level 1 would change the optical mass by"));
    EXPECT_THAT(skin.output, HasSubstr("full resolution"));
    const CliRun bad = renderBall(out, "--detail-levels 4");
    EXPECT_NE(bad.status, 0);
    EXPECT_THAT(bad.output, HasSubstr("--detail-levels: must be 0 to 3 halvings"));
}
