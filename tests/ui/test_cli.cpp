// The command line as a user meets it: `render` writes a picture without an X server, `info` reports
// the volume, `accuracy` writes its report, and mistakes get one clear line on stderr and a non-zero exit.
// The editor's flags: test_cli_editor.cpp.
#include "image_compare.h"
#include "renderer/errors.h"
#include "renderer/io/image.h"
#include "renderer/math/metrics.h"
#include "renderer/model/paraview_preset.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/transfer_function.h"
#include "renderer/io/volume_io.h"
#include "cli_run.h"
#include "scoped_env.h"
#include "test_paths.h"
#include "ui/session.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <sstream>
#include <string>

using ::testing::HasSubstr;
using ::testing::Not;

namespace {

using testing_support::CliRun;
using testing_support::headsq;
using testing_support::runShell;
using testing_support::splatlab;

// Bundled headsq front to back at 96x80 with GPU counters, written to `out`; `flags` say what differs.
CliRun renderHeadsqFrontToBack(const std::filesystem::path& out, const std::string& flags) {
    return splatlab("render \"" + headsq() + "\" --out \"" + out.string() +
                    "\" --compositing sheet-front-to-back --size 96x80 --frames 1 --up -z --counters " + flags);
}

} // namespace

TEST(Cli, RenderWritesAPictureOfTheVolumeHeadless) {
    const auto out = testing_support::testOutputDir() / "cli_headsq.png";
    std::filesystem::remove(out);
    const CliRun r = splatlab("render \"" + headsq() + "\" --out \"" + out.string() +
                           "\" --size 96x80 --frames 1 --up -z --camera 60,15,2.5,30");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("96x80"));
    EXPECT_THAT(r.output, HasSubstr("ms/frame"));
    EXPECT_THAT(r.output, Not(HasSubstr("not applied"))) << "headsq's axes are x, y, z";
    const renderer::Image img = renderer::readImage(out);
    ASSERT_EQ(img.width, 96);
    ASSERT_EQ(img.height, 80);
    // The PNG is opaque; the head covers a good part of the frame and is brighter than the background.
    size_t bright = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) bright += img.pixel(x, y)[0] > 0.2f;
    EXPECT_GT(double(bright) / (96.0 * 80.0), 0.2);
}

// An 8^3 NRRD with the given axes, bright where `bright(x, y, z)`: written for the orientation tests.
std::filesystem::path writeNrrd(const std::string& name, const std::string& directions,
                                const std::function<bool(int, int, int)>& bright) {
    const auto path = testing_support::testOutputDir() / name;
    std::ofstream f(path, std::ios::binary);
    f << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 8 8 8\nspace: left-posterior-superior\n"
         "space directions: " << directions << "\nencoding: raw\n\n";
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) f.put(char(bright(x, y, z) ? 200 : 10));
    return path;
}

// A file is drawn in its world frame: one whose x axis runs the world's -x as the same world volume
// stored with x running +x (not as its stored order); one whose axes are turned 30 degrees about z, seen
// from azimuth 60, as the unturned one from azimuth 30; and a turned one that also mirrors x likewise.
// Axes off orthonormal by a header's rounding are drawn as the orthonormal axes nearest them (sheared
// ones: the next test).
TEST(Cli, RenderDrawsTheFileInItsWorldFrame) {
    const std::string identity = "(1,0,0) (0,1,0) (0,0,1)";
    const std::string c = "0.8660254037844387";   // cos 30 degrees
    // A corner block: low x and low y in index order.
    const auto stored = [](int x, int y, int) { return x < 3 && y < 4; };
    const auto mirroredFile = writeNrrd("cli_x_mirrored.nrrd", "(-1,0,0) (0,1,0) (0,0,1)", stored);
    const auto worldFile =
        writeNrrd("cli_x_as_world.nrrd", identity, [&](int x, int y, int z) { return stored(7 - x, y, z); });
    const auto storedFile = writeNrrd("cli_x_as_stored.nrrd", identity, stored);
    const auto turnedFile = writeNrrd("cli_turned.nrrd", "(" + c + ",0.5,0) (-0.5," + c + ",0) (0,0,1)", stored);
    const auto mirroredTurnedFile =
        writeNrrd("cli_x_mirrored_turned.nrrd", "(-" + c + ",-0.5,0) (-0.5," + c + ",0) (0,0,1)", stored);
    auto render = [](const std::filesystem::path& in, double azimuth) {
        const auto out = std::filesystem::path(in).replace_extension(".exr");
        const CliRun r = splatlab("render \"" + in.string() + "\" --out \"" + out.string() +
                                  "\" --size 48x48 --frames 1 --tf grey-ramp --camera " + std::to_string(azimuth) +
                                  ",20,2.5,30");
        EXPECT_EQ(r.status, 0) << r.output;
        EXPECT_THAT(r.output, Not(HasSubstr("note:")));
        return renderer::readImage(out);
    };
    auto maxDiff = [](const renderer::Image& a, const renderer::Image& b) {
        return renderer::compareImages(a, b).maxAbs;
    };
    const renderer::Image mirrored = render(mirroredFile, 30.0);
    EXPECT_LT(maxDiff(mirrored, render(worldFile, 30.0)), 1e-6);
    EXPECT_GT(maxDiff(mirrored, render(storedFile, 30.0)), 0.05) << "the test volume is symmetric";
    EXPECT_LT(maxDiff(render(turnedFile, 60.0), render(storedFile, 30.0)), 1e-5);
    EXPECT_GT(maxDiff(render(turnedFile, 60.0), render(storedFile, 60.0)), 0.05) << "the turn must show";
    EXPECT_LT(maxDiff(render(mirroredTurnedFile, 60.0), render(worldFile, 30.0)), 1e-5);
    EXPECT_THAT(splatlab("info \"" + mirroredFile.string() + "\"").output,
                HasSubstr("the voxels are reordered"));
    EXPECT_THAT(splatlab("info \"" + turnedFile.string() + "\"").output, HasSubstr("the view turns with them"));
    // Axes turned 40 degrees about (1, 2, 3), their cosines rounded to three digits as some headers print
    // them (their dot products are off by 7e-4), are drawn as the orthonormal axes nearest them, not
    // refused as sheared. Measured: RMSE 1.3e-4, max 7.7e-4 against the exact axes.
    const auto obliqueFile = writeNrrd("cli_oblique.nrrd",
                                       "(0.78275555432476529,0.5487988669638042,-0.29345109608412456) "
                                       "(-0.48195442214065509,0.83288888794212712,0.27205888208546691) "
                                       "(0.39371776331884822,-0.07152554761601948,0.91644444397106362)",
                                       stored);
    const auto roundedFile = writeNrrd("cli_oblique_rounded.nrrd",
                                       "(0.783,0.549,-0.293) (-0.482,0.833,0.272) (0.394,-0.072,0.916)", stored);
    const renderer::ImageError rounded = renderer::compareImages(render(roundedFile, 30.0), render(obliqueFile, 30.0));
    EXPECT_LT(rounded.rmse, 5e-4);
    EXPECT_LT(rounded.maxAbs, 5e-3);
    EXPECT_GT(maxDiff(render(obliqueFile, 30.0), render(storedFile, 30.0)), 0.05) << "the turn must show";
    EXPECT_THAT(splatlab("info \"" + roundedFile.string() + "\"").output,
                HasSubstr("the view turns with them; rounded cosines"));
    EXPECT_THAT(splatlab("info \"" + obliqueFile.string() + "\"").output, Not(HasSubstr("rounded")));

}

// A float NRRD of `dims` voxels whose index steps are the columns of `steps` (in the world), from
// `origin`, holding field(world position) at each voxel.
std::filesystem::path writeFieldNrrd(const std::string& name, glm::ivec3 dims, const glm::dmat3& steps,
                                     const glm::dvec3& origin, const std::function<double(glm::dvec3)>& field) {
    const auto path = testing_support::testOutputDir() / name;
    std::ofstream f(path, std::ios::binary);
    char header[512];
    std::snprintf(header, sizeof header,
                  "NRRD0004\ntype: float\ndimension: 3\nsizes: %d %d %d\nspace: left-posterior-superior\n"
                  "space directions: (%.17g,%.17g,%.17g) (%.17g,%.17g,%.17g) (%.17g,%.17g,%.17g)\n"
                  "space origin: (%.17g,%.17g,%.17g)\nendian: little\nencoding: raw\n\n",
                  dims.x, dims.y, dims.z, steps[0].x, steps[0].y, steps[0].z, steps[1].x, steps[1].y, steps[1].z,
                  steps[2].x, steps[2].y, steps[2].z, origin.x, origin.y, origin.z);
    f << header;
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x) {
                const float v = float(field(origin + steps * glm::dvec3(x, y, z)));
                f.write(reinterpret_cast<const char*>(&v), sizeof v);
            }
    return path;
}

// A scan with a gantry tilt (slices stacked along a tilted axis) is resampled onto the world axes, so it
// draws as the same object sampled on that world grid: a blob placed off-centre, where the tilt would
// move it if it were ignored.
TEST(Cli, ShearedAxesAreResampledSoTheVolumeDrawsWhereItsFileSays) {
    const double tilt = glm::radians(25.0);
    const glm::dvec3 centre{14.0, 9.0, 8.0};
    const auto blob = [&](glm::dvec3 p) {   // two Gaussian lumps, so that a shift or a skew shows
        return 1000.0 * std::exp(-glm::dot(p - centre, p - centre) / 18.0) +
               600.0 * std::exp(-glm::dot(p - centre - glm::dvec3(-6, 5, 4), p - centre - glm::dvec3(-6, 5, 4)) / 8.0);
    };
    const glm::dmat3 tilted(glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, std::sin(tilt), std::cos(tilt)));
    const auto shearedFile = writeFieldNrrd("cli_gantry_tilt.nrrd", {24, 24, 20}, tilted, {0, -4, 0}, blob);
    // The same voxels with the tilt left out, and the blob sampled on the grid the tilted scan resamples to.
    const auto ignoredFile = writeFieldNrrd("cli_gantry_tilt_ignored.nrrd", {24, 24, 20}, glm::dmat3(1.0), {0, -4, 0},
                                            [&](glm::dvec3 p) { return blob(tilted * (p - glm::dvec3(0, -4, 0)) + glm::dvec3(0, -4, 0)); });
    const renderer::Volume grid = renderer::loadVolumeInWorldFrame(shearedFile);
    ASSERT_TRUE(grid.resampled);
    const glm::dmat3 gridSteps(glm::dvec3(grid.spacing.x, 0, 0), glm::dvec3(0, grid.spacing.y, 0),
                               glm::dvec3(0, 0, grid.spacing.z));
    const auto worldFile = writeFieldNrrd("cli_gantry_tilt_world.nrrd", grid.dims, gridSteps, grid.origin, blob);

    auto render = [](const std::filesystem::path& in, std::string* output = nullptr) {
        const auto out = std::filesystem::path(in).replace_extension(".exr");
        const CliRun r = splatlab("render \"" + in.string() + "\" --out \"" + out.string() +
                                  "\" --size 64x64 --frames 1 --tf grey-ramp --window 0,1000 --camera 30,20,2.5,30");
        EXPECT_EQ(r.status, 0) << r.output;
        if (output) *output = r.output;
        return renderer::readImage(out);
    };
    std::string note;
    const renderer::Image sheared = render(shearedFile, &note);
    EXPECT_THAT(note, HasSubstr("note: " + shearedFile.string() + ": its axes are sheared"));
    EXPECT_THAT(note, HasSubstr("resampled (trilinear) onto a grid along the world axes, " +
                                std::to_string(grid.dims.x) + " x " + std::to_string(grid.dims.y) + " x " +
                                std::to_string(grid.dims.z)));
    const renderer::ImageError resampled = renderer::compareImages(sheared, render(worldFile));
    const renderer::ImageError ignored = renderer::compareImages(render(ignoredFile), render(worldFile));
    std::printf("tilted scan vs the world grid: RMSE %.5f (max %.4f); tilt ignored: RMSE %.5f (max %.4f)\n",
                resampled.rmse, resampled.maxAbs, ignored.rmse, ignored.maxAbs);
    EXPECT_LT(resampled.rmse, 0.01);
    EXPECT_GT(ignored.rmse, 5.0 * resampled.rmse) << "the tilt must show when it is left out";
    EXPECT_THAT(splatlab("info \"" + shearedFile.string() + "\"").output,
                HasSubstr("sheared: render and the editor resample the voxels (trilinear) onto a grid along the "
                          "world axes, " + std::to_string(grid.dims.x) + " x " + std::to_string(grid.dims.y) +
                          " x " + std::to_string(grid.dims.z)));
}

TEST(Cli, RenderWritesTheHeatmapAndPrintsGpuCountersWithShadingAndSheets) {
    const auto dir = testing_support::testOutputDir("cli_heatmap");
    const CliRun r = splatlab("render \"" + headsq() + "\" --out \"" + (dir / "img.png").string() + "\" --heatmap \"" +
                              (dir / "heat.exr").string() + "\" --counters --filter adaptive --shading per-splat " +
                              "--surface 8 --compositing sheet-front-to-back --size 64x64 --frames 1 --up -z");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("drawn "));
    EXPECT_THAT(r.output, HasSubstr("GPU bytes per voxel"));
    // The heatmap's three shares add up to the pixel's alpha, and some pixel is covered.
    const renderer::Image heat = renderer::readImage(dir / "heat.exr");
    ASSERT_EQ(heat.width, 64);
    double covered = 0.0;
    for (size_t i = 0; i < heat.rgba.size(); i += 4) {
        ASSERT_NEAR(heat.rgba[i] + heat.rgba[i + 1] + heat.rgba[i + 2], heat.rgba[i + 3], 1e-4);
        covered += heat.rgba[i + 3];
    }
    EXPECT_GT(covered, 64.0);
}

TEST(Cli, TiledSplattingRendersTheSameImageAsTheRasteriser) {
    const auto dir = testing_support::testOutputDir("cli_tiles");
    renderer::Image images[2];
    for (int tiles = 0; tiles < 2; ++tiles) {
        const auto out = dir / (tiles ? "tiles.exr" : "quads.exr");
        const CliRun r =
            renderHeadsqFrontToBack(out, std::string("--opaque-refresh 8 --primitive ") + (tiles ? "tiles" : "quads"));
        ASSERT_EQ(r.status, 0) << r.output;
        if (tiles) {
            EXPECT_THAT(r.output, HasSubstr("splat-tile pairs composited"));
        }
        images[tiles] = renderer::readImage(out);
    }
    const auto d = testing_support::renderDifference(images[0], images[1]);
    EXPECT_LT(d.elsewhere, 1e-4);
    EXPECT_LE(d.atOpaque, 2e-3f);
    EXPECT_GT(renderer::imageStats(images[1]).coveredFraction, 0.2);
}

TEST(Cli, NoOcclusionCullingKeepsHiddenSplatsForTheSameImage) {
    // headsq made dense (--density 30) turns tiles opaque front to back: with culling the splats behind
    // them are dropped, without it they are drawn and early termination skips their pixels, so the image
    // is the same.
    const auto dir = testing_support::testOutputDir("cli_occlusion");
    renderer::Image images[2];
    unsigned long long hidden[2] = {0, 0}, drawn[2] = {0, 0}, computed[2] = {0, 0};
    for (int culled = 0; culled < 2; ++culled) {
        const auto out = dir / (culled ? "culled.exr" : "kept.exr");
        const CliRun r = renderHeadsqFrontToBack(out, std::string("--density 30") + (culled ? "" : " --no-occlusion-culling"));
        ASSERT_EQ(r.status, 0) << r.output;
        const size_t at = r.output.find("hidden behind opaque ");
        ASSERT_NE(at, std::string::npos) << r.output;
        hidden[culled] = std::stoull(r.output.substr(at + 21));
        drawn[culled] = std::stoull(r.output.substr(r.output.find("drawn ") + 6));
        computed[culled] = std::stoull(r.output.substr(r.output.find("footprints computed ") + 20));
        images[culled] = renderer::readImage(out);
    }
    EXPECT_EQ(hidden[0], 0u);
    EXPECT_GT(hidden[1], 1000u);
    EXPECT_EQ(drawn[0], drawn[1] + hidden[1]);   // what culling removed, and only that
    // A hidden splat still costs its footprint (or the bound the occlusion test projects): the same count.
    EXPECT_EQ(computed[0], computed[1]);
    EXPECT_GE(computed[1], drawn[1] + hidden[1]);
    const auto d = testing_support::renderDifference(images[0], images[1]);
    EXPECT_LT(d.elsewhere, 1e-4);
    EXPECT_LE(d.atOpaque, 2e-3f);
    EXPECT_GT(renderer::imageStats(images[1]).coveredFraction, 0.2);
}

TEST(Cli, OcclusionCullingFollowsTheDriverUnlessAFlagSays) {
    // Dense headsq front to back: how many splats were culled says whether culling ran. llvmpipe culls by
    // default, a GPU does not (SPLATLAB_DRIVER_PROFILE=gpu gives llvmpipe the GPU's profile); either flag
    // overrides the driver, and the two together are refused.
    const auto out = testing_support::testOutputDir("cli_occlusion") / "driver.exr";
    auto hidden = [&](const char* profile, const std::string& flags) {
        const testing_support::ScopedEnv forced("SPLATLAB_DRIVER_PROFILE", *profile ? profile : nullptr);
        const CliRun r = renderHeadsqFrontToBack(out, "--density 30 " + flags);
        EXPECT_EQ(r.status, 0) << r.output;
        const size_t at = r.output.find("hidden behind opaque ");
        return at == std::string::npos ? -1LL : std::stoll(r.output.substr(at + 21));
    };
    EXPECT_GT(hidden("", ""), 1000);
    EXPECT_EQ(hidden("gpu", ""), 0);
    EXPECT_GT(hidden("gpu", "--occlusion-culling"), 1000);
    EXPECT_EQ(hidden("", "--no-occlusion-culling"), 0);
    const CliRun both = renderHeadsqFrontToBack(out, "--occlusion-culling --no-occlusion-culling");
    EXPECT_NE(both.status, 0);
    EXPECT_THAT(both.output, HasSubstr("--occlusion-culling"));
}

TEST(Cli, BadRenderOptionsNameTheFlag) {
    const auto out = (testing_support::testOutputDir() / "cli_bad.png").string();
    for (auto [args, flag] : {std::pair{"--shading phong", "--shading"}, std::pair{"--surface 0.5", "--surface"},
                              std::pair{"--primitive lines", "--primitive"}, std::pair{"--opaque-alpha 0", "--opaque-alpha"}}) {
        const CliRun r = splatlab("render \"" + headsq() + "\" --out \"" + out + "\" --size 8x8 --frames 1 " + args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_THAT(r.output, HasSubstr(flag)) << args;
    }
}

TEST(Cli, InfoPrintsDimsTypeSpacingAndRange) {
    const CliRun r = splatlab("info \"" + headsq() + "\"");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("64 x 64 x 93"));
    EXPECT_THAT(r.output, HasSubstr("int16"));
    EXPECT_THAT(r.output, HasSubstr("3.2 x 3.2 x 1.5"));
    EXPECT_THAT(r.output, HasSubstr("0 .. 3926"));
    EXPECT_THAT(r.output, HasSubstr("histogram"));
}

TEST(Cli, MistakesGetOneClearLineAndAFailingExit) {
    const std::string out = (testing_support::testOutputDir() / "never.png").string();
    const std::string raw = (testing_support::testOutputDir() / "unnamed.raw").string();
    std::ofstream(raw, std::ios::binary) << "12345678";
    const std::string folder = (testing_support::testOutputDir() / "a_folder").string();
    std::filesystem::create_directories(folder);
    const std::string render = "render \"" + headsq() + "\" --size 8x8 --frames 1 ";
    const std::pair<std::string, std::string> cases[] = {
        {"render \"" + headsq() + "\" --out " + out + " --size 64", "expected WxH"},
        {"render \"" + headsq() + "\" --out " + out + " --camera 1,2,3", "azimuth,elevation,distance,fov"},
        {"render \"" + headsq() + "\" --out " + out + " --camera 0,0,2,200", "fov must be 1..170"},
        {"render \"" + headsq() + "\" --out " + out + " --camera 0,0,1e300,30", "distance must be in [0.001, 1000]"},
        {"render \"" + headsq() + "\" --out " + out + " --density inf", "--density: must be in [1e-06, 1e+06]"},
        {"render \"" + headsq() + "\" --out " + out + " --density 1e300", "--density: must be in [1e-06, 1e+06]"},
        {"render \"" + headsq() + "\" --out " + out + " --heatmap " + out, "is also --out"},
        {"render \"" + raw + "\" --out " + out, "give --raw-dims and --raw-type"},
        {render + "--out " + out + " --tf \"" + folder + "\"", "a_folder: is a folder, expected a transfer function"},
        {render + "--out \"" + folder + "\"", "a_folder: is a folder; name an image file in it"},
        {render + "--out never.bogus", "never.bogus: no image writer for the extension '.bogus'"},
        {render + "--out no_such_folder/x.png", "x.png: cannot write: the folder 'no_such_folder' does not exist"},
        {render + "--out " + out + " --window 0,1e-300", "LO must be below HI (as 32-bit floats the two are equal)"},
        {render + "--out " + out + " --window 0,1e300", "LO and HI must be finite 32-bit floats"},
        {render + "--out " + out + " --opaque-refresh -1", "--opaque-refresh: must be in [0, 4096] slices (0: auto)"},
        {"reference \"" + headsq() + "\" --size 8x8 --out " + out + " --cache \"" + raw + "\"",
         "unnamed.raw: cannot be the ground-truth cache folder"},
        {"reference \"" + headsq() + "\" --size 8x8 --out " + out + " --supersample 0", "--supersample: Value 0 not in range 1 to 8"},
        // The output is checked before the rays are traced (no progress bar).
        {"reference \"" + headsq() + "\" --size 8x8 --no-cache --out no_such_folder/gt.exr", "does not exist"},
        {"render \"" + headsq() + "\" --out " + out + " --compositing sheet", "known: splat-every-sample, xray"},
        {"render \"" + headsq() + "\" --out " + out + " --filter box", "known: reconstruction, low-pass, ewa"},
        {"render \"" + headsq() + "\" --out " + out + " --tf nonsense", "known: ct-skin-bone"},
        {"render \"" + headsq() + "\" --out " + out + " --up w", "expected x, y, z"},
        {"render \"" + headsq() + "\" --out " + out + " --compositing splat-every-sample --primitive tiles",
         "splat-every-sample needs points or quads"},
        {"render no_such_volume.nhdr --out " + out, "no_such_volume.nhdr: cannot open"},
        {"render \"" + headsq() + "\"", "--out is required"},
        {"info", "volume is required"},
        {"frobnicate", "frobnicate"},
    };
    for (const auto& [args, expect] : cases) {
        const CliRun r = splatlab(args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_THAT(r.output, HasSubstr(expect)) << args;
        EXPECT_THAT(r.output, Not(HasSubstr("%"))) << args;   // refused before any progress
    }
}

// X-ray's ground truth from the command line, as the Filters panel has it. Without attenuation the order
// along a ray does not matter: seen from the opposite side (parallel rays, the camera turned 180 degrees)
// the X-ray truth is the same image mirrored left to right. With attenuation (every other mode's truth)
// the other side shows what the front hid.
TEST(Cli, ReferenceTakesCompositingSoXRayHasAGroundTruthFromTheCommandLine) {
    const auto dir = testing_support::testOutputDir("cli_reference_xray");
    const std::string view = "\"" + headsq() + "\" --size 24x16 --up -z --ortho --no-cache ";
    // Largest difference between the view from the front and the mirrored view from behind.
    auto frontAgainstMirroredBack = [&](const std::string& compositing) {
        std::array<renderer::Image, 2> images;
        for (int i = 0; i < 2; ++i) {
            const std::string out = (dir / (compositing + std::to_string(i) + ".exr")).string();
            const CliRun r = splatlab("reference " + view + "--compositing " + compositing + " --camera " +
                                      (i == 0 ? "30,20,2.5,30" : "210,-20,2.5,30") + " --out \"" + out + "\"");
            EXPECT_EQ(r.status, 0) << r.output;
            images[size_t(i)] = renderer::readImage(out);
        }
        const renderer::Image& front = images[0];
        double largest = 0.0;
        for (int y = 0; y < front.height; ++y)
            for (int x = 0; x < front.width; ++x)
                for (int c = 0; c < 4; ++c)
                    largest = std::max(largest, double(std::abs(front.rgba[size_t(y * front.width + x) * 4 + size_t(c)] -
                                                                images[1].rgba[size_t(y * front.width + front.width - 1 - x) * 4 + size_t(c)])));
        return largest;
    };
    EXPECT_LT(frontAgainstMirroredBack("xray"), 1e-3);
    EXPECT_GT(frontAgainstMirroredBack("sheet-front-to-back"), 0.05);
    const CliRun r = splatlab("reference " + view + "--compositing sideways --out \"" + (dir / "x.exr").string() + "\"");
    EXPECT_NE(r.status, 0);
    EXPECT_THAT(r.output, HasSubstr("--compositing"));
}

TEST(Cli, CompareReportsTheErrorWritesTheDifferenceAndRefusesWhatItCannotMeasure) {
    const auto dir = testing_support::testOutputDir("cli_compare");
    renderer::Image a(16, 8), b(16, 8);
    std::fill(a.rgba.begin(), a.rgba.end(), 0.5f);
    b.rgba = a.rgba;
    b.rgba[(3 * 16 + 5) * 4 + 1] = 0.75f;   // one channel of pixel (5, 3) differs by 0.25
    const std::string fa = (dir / "a.exr").string(), fb = (dir / "b.exr").string(), diff = (dir / "diff.exr").string();
    renderer::writeImage(a, fa);
    renderer::writeImage(b, fb);
    std::filesystem::remove(diff);

    const CliRun r = splatlab("compare \"" + fa + "\" \"" + fb + "\" --diff \"" + diff + "\" --gain 2");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("max error 0.250000 at (5, 3)"));
    EXPECT_THAT(r.output, Not(HasSubstr("note:")));
    const renderer::Image d = renderer::readImage(diff);
    EXPECT_FLOAT_EQ(d.rgba[(3 * 16 + 5) * 4 + 1], 0.5f);   // |A - B| x gain
    EXPECT_FLOAT_EQ(d.rgba[(3 * 16 + 6) * 4 + 1], 0.0f);

    // A 8-bit composited PNG against a float EXR: the figures come with a note that they mix two kinds.
    const std::string png = (dir / "a.png").string();
    renderer::writeImage(a, png);
    EXPECT_THAT(splatlab("compare \"" + png + "\" \"" + fb + "\"").output, HasSubstr("note: one image is 8-bit"));

    renderer::writeImage(renderer::Image(8, 8), dir / "small.exr");
    renderer::Image nan = a;
    nan.rgba[(2 * 16 + 7) * 4] = std::nanf("");
    const std::string fnan = (dir / "nan.exr").string();
    renderer::writeImage(nan, fnan);
    const std::pair<std::string, std::string> refused[] = {
        {"compare \"" + fa + "\" \"" + fb + "\" --gain 0", "--gain: must be a finite number > 0"},
        {"compare \"" + fa + "\" \"" + fb + "\" --gain inf", "--gain: must be a finite number > 0"},
        {"compare \"" + fa + "\" \"" + fb + "\" --diff \"" + fb + "\"", "is an image being compared"},
        {"compare \"" + fnan + "\" \"" + fb + "\"", "nan.exr: a pixel is not a finite number (at (7, 2))"},
        {"compare \"" + fa + "\" \"" + fnan + "\"", "nan.exr: a pixel is not a finite number (at (7, 2))"},
        {"compare \"" + fa + "\" \"" + (dir / "small.exr").string() + "\"", "a.exr: 16x8 px, but "},
    };
    for (const auto& [args, expect] : refused) {
        const CliRun bad = splatlab(args);
        EXPECT_NE(bad.status, 0) << args;
        EXPECT_THAT(bad.output, HasSubstr(expect)) << args;
    }
    EXPECT_EQ(renderer::readImage(fb).rgba, b.rgba);   // the --diff that named it left it alone
}

TEST(Cli, EditorFlagMistakesNameTheFlagAndWhatItTakes) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::pair<std::string, std::string> cases[] = {
        {"--frames 3 --tab Nope", "--tab: no panel called 'Nope' (panels: Transfer function, Settings, Viewport, "
                                  "Stats, Performance, Filters, Help)"},
        {"--frames 3 --spin 200", "--spin takes -90 to 90 degrees a second"},
        {"--frames -1", "--frames"},
        // Read on the worker: a volume that fails still ends a scripted run with the reader's error.
        {"--frames 3 no_such_volume.nhdr", "splatlab editor: no_such_volume.nhdr: cannot open"},
    };
    for (const auto& [args, expect] : cases) {
        const CliRun r = runShell("LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 640x480x24\" \"" SPLATLAB_EXE
                             "\" editor " + args + " 2>&1");
        EXPECT_NE(r.status, 0) << args;
        EXPECT_THAT(r.output, HasSubstr(expect)) << args;
    }
}

// Parallel axes cannot be resampled: `info` says so naming the file (it once printed "splatlab: : field").
TEST(Cli, InfoNamesTheFileWhoseAxesAreParallel) {
    const auto file = testing_support::testOutputDir("cli_info") / "parallel_axes.nrrd";
    ASSERT_TRUE(testing_support::writeFile(file, "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\n"
                                                 "space dimension: 3\nspace directions: (1,0,0) (1,0,0) (0,0,1)\n"
                                                 "encoding: raw\n\n" + std::string(8, '\x10')));
    const CliRun r = splatlab("info \"" + file.string() + "\"");
    EXPECT_THAT(r.output, HasSubstr(file.string() + ": field 'directions'")) << r.output;
    EXPECT_THAT(r.output, Not(HasSubstr("splatlab: : "))) << r.output;
}

TEST(Cli, InfoReportsOrientationPercentilesAndGradientsWithAProgressBar) {
    const CliRun r = splatlab("info \"" + headsq() + "\" --gradients");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr("p1..p99"));
    EXPECT_THAT(r.output, HasSubstr("100.0%"));   // the progress bar reached its end
    EXPECT_THAT(r.output, HasSubstr("gradient magnitude  min 0"));
}

TEST(Cli, RenderTakesAWindowInDataUnits) {
    const auto out = testing_support::testOutputDir() / "cli_window.png";
    for (const char* window : {"p1-99", "500,3000"}) {
        const CliRun r = splatlab("render \"" + headsq() + "\" --out \"" + out.string() +
                                  "\" --size 32x32 --frames 1 --window " + window);
        EXPECT_EQ(r.status, 0) << window << ": " << r.output;
    }
    const CliRun bad =
        splatlab("render \"" + headsq() + "\" --out \"" + out.string() + "\" --window 3000,500");
    EXPECT_NE(bad.status, 0);
    EXPECT_THAT(bad.output, HasSubstr("LO must be below HI"));
    // A window above every voxel makes each one class 0, which the TF leaves clear: the frame says it
    // drew nothing rather than list no passes.
    const CliRun clear = splatlab("render \"" + headsq() + "\" --out \"" + out.string() +
                                  "\" --size 32x32 --frames 1 --window 100000,200000");
    EXPECT_EQ(clear.status, 0) << clear.output;
    EXPECT_THAT(clear.output, HasSubstr("in the last frame: no pass ran"));
    EXPECT_THAT(clear.output, HasSubstr(" 0 splats"));
}

TEST(Cli, TfListsThePresetsAndWritesOneAsAFileTheEditorLoads) {
    const CliRun list = splatlab("tf");
    ASSERT_EQ(list.status, 0) << list.output;
    std::string names;
    for (const std::string& name : renderer::builtinPresetNames()) names += name + "\n";
    EXPECT_EQ(list.output, names);

    // Printed, it parses back to the preset itself; written with --out, it loads as the preset.
    const CliRun printed = splatlab("tf fire");
    ASSERT_EQ(printed.status, 0) << printed.output;
    EXPECT_EQ(renderer::transferFunctionFromJson(nlohmann::json::parse(printed.output), "stdout", "?"),
              renderer::builtinPreset("fire"));
    const auto file = testing_support::testOutputDir() / "cli_tf_ct-bone.json";
    std::filesystem::remove(file);
    const CliRun written = splatlab("tf ct-bone --out \"" + file.string() + "\"");
    ASSERT_EQ(written.status, 0) << written.output;
    EXPECT_EQ(renderer::loadTransferFunction(file), renderer::builtinPreset("ct-bone"));
    // A JSON file goes through as it loads: the editor's own round trip.
    const CliRun again = splatlab("tf \"" + file.string() + "\"");
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_EQ(again.output, renderer::transferFunctionText(renderer::builtinPreset("ct-bone")));

    const CliRun unknown = splatlab("tf fyre");
    EXPECT_NE(unknown.status, 0);
    EXPECT_THAT(unknown.output, HasSubstr("unknown transfer-function preset 'fyre' (known: ct-skin-bone,"));
    const CliRun notJson = splatlab("tf \"" + headsq() + "\"");
    EXPECT_NE(notJson.status, 0);
    EXPECT_THAT(notJson.output, HasSubstr("headsq.nhdr: not valid JSON"));
}

TEST(Cli, TfToParaViewSaysItLeavesOutTheGradientOpacity) {
    // A TF with gradient opacity (a file of SplatLab's own) exported as a ParaView preset: the colour and
    // opacity points are written, and a note says the gradient opacity is not; without one, no note.
    renderer::TransferFunction tf = renderer::builtinPreset("ct-bone");
    tf.gradientOpacity = {{0.0, 0.0}, {20.0, 1.0}};
    const auto file = testing_support::testOutputDir() / "cli_tf_gradient.json";
    renderer::saveTransferFunction(tf, file);
    const auto out = testing_support::testOutputDir() / "cli_tf_gradient_paraview.json";
    const CliRun withGradient = splatlab("tf \"" + file.string() + "\" --paraview --out \"" + out.string() + "\"");
    ASSERT_EQ(withGradient.status, 0) << withGradient.output;
    EXPECT_THAT(withGradient.output, HasSubstr("the TF's 2 gradient opacity points are not written"));
    const renderer::TransferFunction back = renderer::loadParaViewPreset(out);
    EXPECT_EQ(back.opacities.size(), tf.opacities.size());
    EXPECT_TRUE(back.gradientOpacity.empty());
    const CliRun without = splatlab("tf ct-bone --paraview --out \"" + out.string() + "\"");
    ASSERT_EQ(without.status, 0) << without.output;
    EXPECT_THAT(without.output, Not(HasSubstr("gradient opacity")));
}

// A Slicer presets.xml through --tf: `tf FILE.xml#NAME` converts the preset named, its gradient opacity too,
// and an unknown name lists the file's presets.
TEST(Cli, TfConvertsASlicerPresetPickedByName) {
    const auto file = testing_support::testOutputDir() / "cli_slicer_presets.xml";
    std::ofstream(file) << R"(<MRML>
  <VolumeProperty name="Flat" scalarOpacity="4 0 0 100 0.5" colorTransfer="8 0 0 0 0 100 1 1 1"/>
  <VolumeProperty name="Edges" gradientOpacity="4 0 0 50 1" scalarOpacity="4 0 0 100 0.8"
    colorTransfer="8 0 1 0 0 100 1 1 0"/>
</MRML>)";
    const CliRun edges = splatlab("tf \"" + file.string() + "#Edges\"");
    ASSERT_EQ(edges.status, 0) << edges.output;
    const std::string json = edges.output.substr(edges.output.find('{'));
    const renderer::TransferFunction tf =
        renderer::transferFunctionFromJson(nlohmann::json::parse(json), "stdout", "?");
    EXPECT_EQ(tf.name, "Edges");
    EXPECT_EQ(tf.opacities, (std::vector<renderer::OpacityPoint>{{0, 0.0}, {100, 0.8}}));
    EXPECT_EQ(tf.colours[1].colour, glm::dvec3(1, 1, 0));
    EXPECT_EQ(tf.gradientOpacity, (std::vector<renderer::GradientOpacityPoint>{{0, 0.0}, {50, 1.0}}));
    const CliRun unknown = splatlab("tf \"" + file.string() + "#Bone\"");
    EXPECT_NE(unknown.status, 0);
    EXPECT_THAT(unknown.output, HasSubstr("no preset named 'Bone' (it holds: Flat, Edges)"));
}

// `phantom` writes an int16 NRRD that info and the loader read back as it says; a size, a file name or
// a budget it cannot honour is one line naming it, and nothing is written.
TEST(Cli, PhantomWritesAnInt16NrrdThatInfoReadsBack) {
    const auto dir = testing_support::testOutputDir("cli_phantom");
    const auto header = dir / "head32.nhdr", data = dir / "head32.raw";
    std::filesystem::remove(header);
    std::filesystem::remove(data);
    const CliRun made = splatlab("phantom --size 32 --seed 3 --noise 10 --out \"" + header.string() + "\"");
    ASSERT_EQ(made.status, 0) << made.output;
    EXPECT_THAT(made.output, HasSubstr("head32.raw: phantom 32 x 32 x 32 int16 HU, spacing 8 x 8 x 8 mm"));
    EXPECT_THAT(made.output, HasSubstr("65536 bytes of voxels"));
    EXPECT_EQ(std::filesystem::file_size(data), 32u * 32u * 32u * 2u);

    const CliRun info = splatlab("info \"" + header.string() + "\"");
    ASSERT_EQ(info.status, 0) << info.output;
    EXPECT_THAT(info.output, HasSubstr("dims     32 x 32 x 32"));
    EXPECT_THAT(info.output, HasSubstr("type     int16"));
    EXPECT_THAT(info.output, HasSubstr("spacing  8 x 8 x 8"));
    const renderer::Volume v = renderer::loadVolume(header);
    EXPECT_EQ(v.type, renderer::VoxelType::I16);
    EXPECT_LT(v.range.lo, -1000.0f) << "air with noise";
    EXPECT_GT(v.range.hi, 500.0f) << "the skull";

    const CliRun nonCubic = splatlab("phantom --size 24x20x16 --gzip --out \"" + (dir / "small.nrrd").string() + "\"");
    ASSERT_EQ(nonCubic.status, 0) << nonCubic.output;
    EXPECT_EQ(renderer::loadVolume(dir / "small.nrrd").dims, glm::ivec3(24, 20, 16));

    const CliRun badSize = splatlab("phantom --size 32x32 --out \"" + header.string() + "\"");
    EXPECT_NE(badSize.status, 0);
    EXPECT_THAT(badSize.output, HasSubstr("--size: '32x32': expected N or WxHxD"));
    const CliRun badName = splatlab("phantom --size 32 --out \"" + (dir / "head.raw").string() + "\"");
    EXPECT_NE(badName.status, 0);
    EXPECT_THAT(badName.output, HasSubstr("expected a .nhdr or .nrrd file name"));
    const auto big = dir / "big.nrrd";
    std::filesystem::remove(big);
    const CliRun overBudget = runShell("SPLATLAB_MEMORY_BUDGET_MB=1 \"" SPLATLAB_EXE "\" phantom --size 128 --out \"" +
                                  big.string() + "\" 2>&1");
    EXPECT_NE(overBudget.status, 0);
    EXPECT_THAT(overBudget.output, HasSubstr("size 128 x 128 x 128 voxels need 4 MiB as int16, more than the "
                                             "memory budget of 1 MiB"));
    EXPECT_FALSE(std::filesystem::exists(big));
}

TEST(Cli, AccuracyWritesTheReportWithItsTablesAndThumbnails) {
    // The docs/accuracy.md generator at a tiny scale: one hard case, a 64-voxel board, 4^3 Marschner-Lobb.
    const auto dir = testing_support::testOutputDir() / "cli_accuracy";
    std::filesystem::remove_all(dir);
    const CliRun r = splatlab("accuracy --out \"" + dir.string() + "\" --cache \"" + (dir / "cache").string() +
                              "\" --only one-voxel --board 64 --marschner-lobb 4 --kernel-scales 0.6,0.7");
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream in(dir / "accuracy.md");
    const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const char* part : {"## Hard cases", "| one-voxel |", "## The paper's claims per region", "| minified |",
                             "## Kernel scale on Marschner-Lobb", "| 0.60 |", "| 0.70 |",
                             "covers only the hard cases named by `--only`: one-voxel.", "## Image-aligned slabs",
                             "| one-voxel | ewa |", "## Post-classified slabs"})
        EXPECT_THAT(md, HasSubstr(part));
    EXPECT_THAT(md, Not(HasSubstr("| zebra |")));
    EXPECT_THAT(md, Not(HasSubstr("## Scans"))) << "the scans' truths take minutes: the whole report only";
    EXPECT_TRUE(std::filesystem::exists(dir / "images" / "accuracy" / "one-voxel_ewa.png"));
    EXPECT_TRUE(std::filesystem::exists(dir / "images" / "accuracy" / "board_regions.png"));
    const CliRun bad = splatlab("accuracy --out \"" + dir.string() + "\" --kernel-scales 0");
    EXPECT_NE(bad.status, 0);
    EXPECT_THAT(bad.output, HasSubstr("--kernel-scales"));
    // A misspelt case is refused before anything runs, and the report stays as it was.
    const CliRun misspelt = splatlab("accuracy --out \"" + dir.string() + "\" --only one-voxle");
    EXPECT_NE(misspelt.status, 0);
    EXPECT_THAT(misspelt.output, HasSubstr("--only: no hard case 'one-voxle' (known: near-plane,"));
    std::ifstream again(dir / "accuracy.md");
    EXPECT_EQ(std::string((std::istreambuf_iterator<char>(again)), std::istreambuf_iterator<char>()), md);
}

TEST(Cli, RenderOpensASessionAsTheFlagsItStandsForWouldDrawIt) {
    // A view designed in the editor (saved as a session) rendered headless at another size.
    const std::filesystem::path dir = testing_support::testOutputDir("cli_session");
    ui::EditorState state;
    state.camera.azimuthDeg = 75.0;
    state.camera.elevationDeg = 10.0;
    state.camera.distance = 2.2;
    state.camera.up = glm::dvec3(0.0, 0.0, -1.0);
    state.tf = renderer::builtinPreset("fire");
    state.window.mode = renderer::WindowMode::Custom;
    state.window.custom = {200.0f, 3000.0f};
    state.settings.filter = renderer::FilterMode::Adaptive;
    state.settings.compositing = renderer::Compositing::SheetFrontToBack;
    state.settings.kernelScale = 0.9;
    state.background = {0.2f, 0.3f, 0.4f};
    ui::saveSession(state, headsq(), dir / "view.json");

    const std::string size = " --size 160x120 --frames 1";
    const CliRun s = splatlab("render --session \"" + (dir / "view.json").string() + "\"" + size + " -o \"" +
                              (dir / "session.exr").string() + "\"");
    ASSERT_EQ(s.status, 0) << s.output;
    EXPECT_THAT(s.output, HasSubstr("adaptive, sheet-front-to-back"));
    const CliRun f = splatlab("render \"" + headsq() + "\" --up -z --camera 75,10,2.2,30 --tf fire --window 200,3000 "
                              "--filter adaptive --compositing sheet-front-to-back --kernel-scale 0.9" + size +
                              " -o \"" + (dir / "flags.exr").string() + "\"");
    ASSERT_EQ(f.status, 0) << f.output;
    const renderer::Image a = renderer::readImage(dir / "session.exr"), b = renderer::readImage(dir / "flags.exr");
    ASSERT_EQ(a.width, 160);
    ASSERT_EQ(a.rgba.size(), b.rgba.size());
    const auto d = testing_support::renderDifference(a, b);
    EXPECT_LE(d.elsewhere, 1e-6f);
    EXPECT_LE(d.atOpaque, 2e-3f);
    EXPECT_GT(renderer::imageStats(a).coveredFraction, 0.2);

    // A PNG goes over the session's background, as the editor shows it.
    ASSERT_EQ(splatlab("render --session \"" + (dir / "view.json").string() + "\"" + size + " -o \"" +
                       (dir / "session.png").string() + "\"").status, 0);
    const renderer::Image png = renderer::readImage(dir / "session.png");
    EXPECT_NEAR(png.pixel(0, 0)[2], 0.4, 0.5 / 255.0);   // a corner the volume leaves empty

    // What the session sets cannot also come from a flag; a session without a volume needs one.
    const CliRun clash = splatlab("render --session \"" + (dir / "view.json").string() + "\" --camera 1,2,3,30 -o x.png");
    EXPECT_NE(clash.status, 0);
    EXPECT_THAT(clash.output, HasSubstr("--camera: not with --session: the session sets it"));
    ui::saveSession(state, {}, dir / "no_volume.json");
    const CliRun none = splatlab("render --session \"" + (dir / "no_volume.json").string() + "\" -o x.png");
    EXPECT_NE(none.status, 0);
    EXPECT_THAT(none.output, HasSubstr("no_volume.json"));
    EXPECT_THAT(none.output, HasSubstr("volume"));
    const CliRun nothing = splatlab("render -o x.png");
    EXPECT_NE(nothing.status, 0);
    EXPECT_THAT(nothing.output, HasSubstr("--session"));
}
