// `splatlab render --orbit STEP` (app/orbit_measure.h): each frame of a turn against the one before, the
// slice axis each takes, and the summary; the command line writes the CSV and refuses bad steps.
#include "cli_run.h"
#include "orbit_measure.h"

#include "renderer/gl/gl_context.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/math/metrics.h"
#include "renderer/model/procedural.h"
#include "renderer/model/volume.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>

using namespace renderer;
using testing::HasSubstr;
using testing_support::CliRun;
using testing_support::splatlab;

TEST(OrbitPopping, EachStepIsTheRmseAgainstTheFrameBeforeWithItsSliceAxis) {
    std::unique_ptr<HeadlessGl> context;
    try {
        context = HeadlessGl::create();
    } catch (const std::exception& e) {
        if (const char* r = std::getenv("REQUIRE_GL"); r && std::string(r) == "1") FAIL() << e.what();
        GTEST_SKIP() << "no headless GL context: " << e.what();
    }
    // A volume with no symmetry a turn could map onto itself: a ramp along x, a slab at low y, 16 x 12 x 10.
    Volume v;
    v.dims = {16, 12, 10};
    v.values.floats().resize(v.voxelCount());
    for (int z = 0; z < 10; ++z)
        for (int y = 0; y < 12; ++y)
            for (int x = 0; x < 16; ++x)
                v.values.floats()[v.index(x, y, z)] = float(x * x) / 225.0f * 0.7f + (y < 4 && z > 3 ? 0.3f : 0.0f);
    updateRange(v);
    const SplatScene scene =
        buildSplatScene(v, fromSharedPoints("ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {1.0, {1.0, 0.8, 0.3}, 0.8}}));
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    const Camera start{.azimuthDeg = 10, .elevationDeg = 20};
    SplatRenderer gl;
    gl.setScene(scene);
    const OrbitSummary orbit = measureOrbit([&](const ImagePlane& p) { gl.render(p, s); return gl.readback(); },
                                            scene, start, 32, 28, 45.0);
    ASSERT_EQ(orbit.steps.size(), 8u);
    // The same frames drawn one by one: each step's RMSE and axis, the last frame against the first.
    std::vector<Image> frames;
    for (int k = 0; k < 8; ++k) {
        Camera c = start;
        c.azimuthDeg += 45.0 * k;
        const ImagePlane plane = makeImagePlane(c, scene.centre, scene.radius, 32, 28, scene.axes);
        gl.render(plane, s);
        frames.push_back(gl.readback());
        EXPECT_DOUBLE_EQ(orbit.steps[size_t(k)].azimuthDeg, c.azimuthDeg);
        EXPECT_EQ(orbit.steps[size_t(k)].axis, chooseTraversal(plane).axis) << k;
    }
    // GL frames drawn twice differ in the last bits (llvmpipe's threads sum in another order): 1e-6.
    std::vector<double> rmse;
    for (int k = 0; k < 8; ++k) {
        rmse.push_back(compareImages(frames[size_t(k)], frames[size_t((k + 7) % 8)]).rmse);
        EXPECT_NEAR(orbit.steps[size_t(k)].rmse, rmse.back(), 1e-6) << k;
    }
    EXPECT_GT(*std::min_element(rmse.begin(), rmse.end()), 0.0) << "45 degrees apart, no two frames agree";
    const double largest = *std::max_element(rmse.begin(), rmse.end());
    EXPECT_NEAR(orbit.maxRmse, largest, 1e-6);
    EXPECT_NEAR(rmse[orbit.worst], largest, 1e-6);
    EXPECT_LT(compareImages(orbit.worstFrame, frames[orbit.worst]).rmse, 1e-6) << "the frame after the largest jump";
    std::vector<double> sorted = rmse;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_NEAR(orbit.medianRmse, sorted[3], 1e-6) << "nearest rank: the 4th of 8";
    EXPECT_NEAR(orbit.p90Rmse, sorted[7], 1e-6);
    // Each step against the median of the 3 on each side (8 frames leave 3).
    ASSERT_EQ(orbit.localSide, 3u);
    double largestLocal = 0.0;
    for (int k = 0; k < 8; ++k) {
        std::vector<double> around;
        for (int d = 1; d <= 3; ++d) around.push_back(rmse[size_t((k + d) % 8)]), around.push_back(rmse[size_t((k + 8 - d) % 8)]);
        std::sort(around.begin(), around.end());
        const double ratio = rmse[size_t(k)] / around[2];   // nearest rank: the 3rd of 6
        EXPECT_NEAR(orbit.steps[size_t(k)].localRatio, ratio, 1e-4) << k;
        largestLocal = std::max(largestLocal, ratio);
    }
    EXPECT_NEAR(orbit.maxLocalRatio, largestLocal, 1e-4);
    // A turn about z from azimuth 10 in steps of 45 slices along x and y by turns: every step switches
    // axis or not as the frames say.
    int switches = 0;
    for (int k = 0; k < 8; ++k) switches += orbit.steps[size_t(k)].axis != orbit.steps[size_t((k + 7) % 8)].axis;
    EXPECT_EQ(orbit.axisSwitches, switches);
    EXPECT_GT(switches, 0);
}

TEST(OrbitPopping, TheCommandLineWritesTheCsvAndTheWorstFrameAndRefusesBadSteps) {
    const std::filesystem::path dir = testing_support::testOutputDir("cli_orbit");
    std::filesystem::remove(dir / "orbit.csv");
    const CliRun r = splatlab("render \"" + testing_support::headsq() + "\" --up -z --size 24x20 --orbit 45 --orbit-csv \"" +
                              (dir / "orbit.csv").string() + "\" --out \"" + (dir / "worst.png").string() + "\"");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("8 frames, 45 deg apart: RMSE between neighbours median"));
    EXPECT_TRUE(std::filesystem::exists(dir / "worst.png"));
    std::ifstream in(dir / "orbit.csv");
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "azimuth_deg,axis,rmse,local_ratio");
    double largest = 0.0;
    int rows = 0;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string azimuth, axis, rmse;
        std::getline(fields, azimuth, ',');
        std::getline(fields, axis, ',');
        std::getline(fields, rmse, ',');
        EXPECT_NEAR(std::stod(azimuth), 30.0 + 45.0 * rows, 1e-9) << line;   // from render's camera, 30,20,...
        EXPECT_TRUE(axis == "0" || axis == "1" || axis == "2") << line;
        largest = std::max(largest, std::stod(rmse));
        ++rows;
    }
    EXPECT_EQ(rows, 8);
    std::smatch printed;
    ASSERT_TRUE(std::regex_search(r.output, printed, std::regex(R"(largest ([0-9.]+) \()"))) << r.output;
    EXPECT_NEAR(std::stod(printed[1]), largest, 5e-7);

    const std::pair<std::string, std::string> bad[] = {
        {"--orbit 7", "--orbit 7: expected a step in degrees that divides 360"},
        {"--orbit 0", "--orbit 0: expected a step in degrees that divides 360"},
        {"--orbit 45 --counters", "compares whole frames: not with --heatmap or --counters"},
    };
    for (const auto& [flags, message] : bad) {
        const CliRun b = splatlab("render \"" + testing_support::headsq() + "\" --size 24x20 " + flags + " --out \"" +
                                  (dir / "bad.png").string() + "\"");
        EXPECT_NE(b.status, 0) << flags;
        EXPECT_THAT(b.output, HasSubstr(message)) << flags;
    }
}
