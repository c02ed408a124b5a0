// The editor from the command line: its flags, sessions beside flags, --measure-interactive, and that it
// saves and frames views as `render` draws them.
#include "image_compare.h"
#include "renderer/errors.h"
#include "renderer/io/image.h"
#include "renderer/math/metrics.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/transfer_function.h"
#include "renderer/io/volume_io.h"
#include "cli_run.h"
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
} // namespace

// --measure-interactive on a phantom of 4.9 M voxels (levels of detail): the editor turns the camera,
// waits for each full frame, prints its measurements and closes by itself; the figures hang together.
TEST(Cli, EditorMeasuresEditToFirstImageAndUiFramesThenCloses) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path phantom = testing_support::testOutputDir() / "phantom170.nhdr";
    ASSERT_EQ(splatlab("phantom --size 170 --out \"" + phantom.string() + "\"").status, 0);
    const CliRun r = runShell("LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE
                         "\" editor \"" + phantom.string() + "\" --tf ct-skin-bone --window -1140,2860 --fit "
                         "--size 1280x800 --measure-interactive 3 2>&1");
    ASSERT_EQ(r.status, 0) << r.output;
    const size_t at = r.output.find("interactive_result ");
    ASSERT_NE(at, std::string::npos) << r.output;
    std::map<std::string, double> v;
    std::istringstream line(r.output.substr(at, r.output.find('\n', at) - at));
    for (std::string field; line >> field;)
        if (const size_t eq = field.find('='); eq != std::string::npos && field.rfind("volume=", 0) != 0)
            v[field.substr(0, eq)] = std::atof(field.c_str() + eq + 1);
    EXPECT_EQ(v["edits"], 3.0);
    EXPECT_GT(v["first_image_ms"], 0.0);
    EXPECT_GE(v["full_ms"], v["first_image_ms"]);
    EXPECT_GE(v["ui_frames"], 1.0);
    EXPECT_GE(v["ui_p95_ms"], v["ui_p50_ms"]);
    EXPECT_GT(v["level0_ms"], 0.0);
    // Where the full frame misses the 150 ms budget, the first images come from a level, and each level
    // drawn before a full frame has its error against it.
    if (v["level0_ms"] > 180.0) {
        EXPECT_GT(v["first_level_mean"], 0.0);
        EXPECT_TRUE(v.count("level1_rmse") || v.count("level2_rmse") || v.count("level3_rmse")) << r.output;
    }
}

TEST(Cli, EditorSavesTheViewAsRenderDrawsItAndNamesAFileItCannotWrite) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path dir = testing_support::testOutputDir();
    const std::string editor = "LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE
                               "\" editor \"" + headsq() + "\" --up -z --camera 60,15,2.5,30 --size 1280x800 --frames 4 ";
    for (const bool heatmap : {false, true}) {
        // Settings > Files > Save image, scripted: what the viewport shows, at its size.
        const std::filesystem::path saved = dir / (heatmap ? "editor_saved_heatmap.exr" : "editor_saved_view.exr");
        std::filesystem::remove(saved);
        const CliRun e = runShell(editor + (heatmap ? "--heatmap " : "") + "--save-image \"" + saved.string() + "\" 2>&1");
        ASSERT_EQ(e.status, 0) << e.output;
        EXPECT_THAT(e.output, HasSubstr("wrote " + saved.string() + ", "));   // the whole path, then the size
        const renderer::Image fromEditor = renderer::readImage(saved);
        ASSERT_GT(fromEditor.width, 400);
        ASSERT_GT(fromEditor.height, 300);
        EXPECT_GT(renderer::imageStats(fromEditor).coveredFraction, 0.2);

        // The same view from `splatlab render` at that size, with no --compositing: render's default
        // is the editor's starting mode. The editor lights a CT preset (headsq opens in ct-skin-bone) per
        // splat unless --shading says otherwise; render stays unlit unless told.
        const std::filesystem::path image = dir / "render_view.exr", heat = dir / "render_heatmap.exr";
        const CliRun r = splatlab("render \"" + headsq() + "\" --up -z --camera 60,15,2.5,30 --shading per-splat --size " +
                                  std::to_string(fromEditor.width) + "x" + std::to_string(fromEditor.height) +
                                  " --frames 1 -o \"" + image.string() + "\"" +
                                  (heatmap ? " --heatmap \"" + heat.string() + "\"" : ""));
        ASSERT_EQ(r.status, 0) << r.output;
        const renderer::Image fromCli = renderer::readImage(heatmap ? heat : image);
        ASSERT_EQ(fromCli.rgba.size(), fromEditor.rgba.size());
        const auto d = testing_support::renderDifference(fromCli, fromEditor);
        EXPECT_LE(d.elsewhere, 1e-5f) << (heatmap ? "heatmap" : "image");
        EXPECT_LE(d.atOpaque, 2e-3f) << (heatmap ? "heatmap" : "image");
    }
    const std::string missing = (dir / "no_such_folder" / "view.png").string();
    const CliRun bad = runShell(editor + "--save-image \"" + missing + "\" 2>&1");
    EXPECT_NE(bad.status, 0);
    EXPECT_THAT(bad.output, HasSubstr(missing));
}

TEST(Cli, TheEditorTakesRendersLookAndSplattingFlagsAndSavesWhatRenderDraws) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path dir = testing_support::testOutputDir();
    // headsq's voxels without their header, read through --raw-*: unit spacing, so a taller head.
    const std::filesystem::path raw = dir / "headerless_head.raw";
    std::filesystem::copy_file(testing_support::assetDir() / "volumes" / "headsq_64x64x93_int16.raw", raw,
                               std::filesystem::copy_options::overwrite_existing);
    const std::string volume = "\"" + raw.string() + "\" --raw-dims 64x64x93 --raw-type int16 --up -z ";
    // Every flag here differs from its default, and each changes the picture.
    const std::string flags = "--camera 60,15,2.5,30 --ortho --window 300,2600 --kernel-scale 0.9 --cutoff 2.5 "
                              "--density 2 --shading per-splat --filter adaptive --c-min 0.6 --patch-size 4 "
                              "--compositing sheet-back-to-front --tf ct-bone ";
    const std::filesystem::path saved = dir / "editor_flags.exr", drawn = dir / "render_flags.exr",
                                plain = dir / "render_plain.exr";
    std::filesystem::remove(saved);
    const CliRun e = runShell("LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE
                         "\" editor " + volume + flags + "--size 1280x800 --frames 4 --save-image \"" +
                         saved.string() + "\" 2>&1");
    ASSERT_EQ(e.status, 0) << e.output;
    const renderer::Image fromEditor = renderer::readImage(saved);
    const std::string size = "--size " + std::to_string(fromEditor.width) + "x" + std::to_string(fromEditor.height);
    const CliRun r = splatlab("render " + volume + flags + size + " --frames 1 -o \"" + drawn.string() + "\"");
    ASSERT_EQ(r.status, 0) << r.output;
    const renderer::Image fromCli = renderer::readImage(drawn);
    ASSERT_EQ(fromCli.rgba.size(), fromEditor.rgba.size());
    EXPECT_GT(renderer::imageStats(fromEditor).coveredFraction, 0.1);
    const auto d = testing_support::renderDifference(fromCli, fromEditor);
    EXPECT_LE(d.elsewhere, 1e-5f);
    EXPECT_LE(d.atOpaque, 2e-3f);
    // And the flags took effect: the same view with the defaults is another picture.
    const CliRun p = splatlab("render " + volume + "--camera 60,15,2.5,30 --tf ct-bone " + size + " --frames 1 -o \"" +
                              plain.string() + "\"");
    ASSERT_EQ(p.status, 0) << p.output;
    EXPECT_GT(renderer::compareImages(renderer::readImage(plain), fromCli).rmse, 0.02);
}

// One range per setting (splat_settings.h): a flag of `render` or the editor takes what a session takes.
TEST(Cli, FlagsAndSessionsAcceptTheSameValuesOfEachSetting) {
    const std::filesystem::path dir = testing_support::testOutputDir();
    const std::string out = (dir / "range.png").string();
    struct Setting {
        const char *flag, *key;
        renderer::SettingRange range;
        double outside;   // how far past each end a value is refused
    };
    const Setting settings[] = {{"--kernel-scale", "kernel_scale", renderer::kKernelScaleRange, 0.01},
                                {"--cutoff", "cutoff", renderer::kCutoffRange, 0.1},
                                {"--density", "density", renderer::kDensityRange, 1e-7},
                                {"--c-min", "c_min", renderer::kCMinRange, 0.005},
                                {"--c-max", "c_max", renderer::kCMaxRange, 0.5},
                                {"--patch-size", "patch_size", renderer::kPatchSizeRange, 1},
                                {"--hysteresis", "hysteresis", renderer::kHysteresisRange, 0.5},
                                {"--opaque-alpha", "opaque_alpha", renderer::kOpaqueAlphaRange, 0.005},
                                {"--opaque-refresh", "opaque_refresh_slices", renderer::kOpaqueRefreshRange, 1},
                                {"--surface", "surface_flatten", renderer::kSurfaceFlattenRange, 0.5},
                                {"--surface-gradient", "surface_gradient", renderer::kSurfaceGradientRange, 0.5}};
    for (const Setting& s : settings) {
        const bool whole = std::string(s.key) == "patch_size" || std::string(s.key) == "opaque_refresh_slices";
        for (const double value : {s.range.lo - s.outside, s.range.lo, s.range.hi, s.range.hi + std::max(s.outside, s.range.hi * 1e-3)}) {
            const bool inside = value >= s.range.lo && value <= s.range.hi;
            char text[32];
            std::snprintf(text, sizeof text, whole ? "%.0f" : "%.9g", value);
            const std::string label = std::string(s.flag) + " " + text;
            // A session with just this value.
            const std::filesystem::path session = dir / "range_session.json";
            std::ofstream(session) << "{\"splatlab_session\": " << ui::kSessionVersion << ", \"splatting\": {\""
                                   << s.key << "\": " << text << "}}";
            ui::EditorState state;
            bool loaded = true;
            try {
                ui::loadSession(session, state);
            } catch (const renderer::LoadError& e) {
                loaded = false;
                EXPECT_THAT(e.what(), HasSubstr(std::string("splatting.") + s.key)) << label;
            }
            EXPECT_EQ(loaded, inside) << label << " in a session";
            const CliRun r = splatlab("render \"" + headsq() + "\" --size 8x8 --frames 1 --out \"" + out + "\" " + label);
            EXPECT_EQ(r.status == 0, inside) << label << "\n" << r.output;
            if (inside) continue;
            EXPECT_THAT(r.output, HasSubstr(std::string(s.flag) + ": must be in [")) << label;
            // The editor refuses it before it opens a window.
            const CliRun e = splatlab("editor " + label);
            EXPECT_NE(e.status, 0) << label;
            EXPECT_THAT(e.output, HasSubstr(std::string(s.flag) + ": must be in [")) << label;
        }
    }
}

TEST(Cli, TheEditorRefusesAFlagBesideASessionThatSetsIt) {
    const std::filesystem::path session = testing_support::testOutputDir() / "refuse_session.json";
    ui::saveSession(ui::EditorState{}, {}, session);
    for (const char* flag : {"--shading per-splat", "--heatmap", "--tf fire", "--camera 1,2,3,30", "--window p1-99",
                             "--split ewa,low-pass"}) {
        const CliRun e = splatlab("editor --session \"" + session.string() + "\" " + flag);
        EXPECT_NE(e.status, 0) << flag;
        const std::string name = std::string(flag).substr(0, std::string(flag).find(' '));
        EXPECT_THAT(e.output, HasSubstr(name + ": not with --session: the session sets it")) << flag;
    }
}

// The rows and columns holding pixels with alpha over 1/255, as fractions of the image's size.
struct Covered {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
Covered coveredBox(const renderer::Image& img) {
    Covered c;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (img.pixel(x, y)[3] > 1.0f / 255.0f)
                c.x0 = std::min(c.x0, x), c.y0 = std::min(c.y0, y), c.x1 = std::max(c.x1, x), c.y1 = std::max(c.y1, y);
    return c;
}

TEST(Cli, FitFramesEverythingVisibleAndTheEditorFramesAsRenderDoes) {
    const std::filesystem::path dir = testing_support::testOutputDir();
    const std::string view = " --up -z --camera 100,-30,6,30 --size 240x160 --compositing sheet-front-to-back --frames 1";
    const std::filesystem::path far = dir / "cli_far.exr", fit = dir / "cli_fit.exr";
    ASSERT_EQ(splatlab("render \"" + headsq() + "\"" + view + " -o \"" + far.string() + "\"").status, 0);
    const CliRun r = splatlab("render \"" + headsq() + "\"" + view + " --fit -o \"" + fit.string() + "\"");
    ASSERT_EQ(r.status, 0) << r.output;
    // Far away the head is small; framed it fills the height, up to the margin (5 % of each half size),
    // and nothing reaches the border.
    const Covered small = coveredBox(renderer::readImage(far)), framed = coveredBox(renderer::readImage(fit));
    EXPECT_LT(small.y1 - small.y0, 100);
    EXPECT_GT(framed.y0, 0);
    EXPECT_GT(framed.x0, 0);
    EXPECT_LT(framed.y1, 159);
    EXPECT_LT(framed.x1, 239);
    EXPECT_GT(framed.y1 - framed.y0, 136) << "framed, the head should fill the height";
    EXPECT_LE(std::abs((framed.y0 + framed.y1) - 159), 4) << "and be centred";

    // The editor's --fit (Settings > Camera > Frame) frames its viewport as render does at that size.
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path saved = dir / "editor_fit.exr";
    const CliRun e = runShell("LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE
                         "\" editor \"" + headsq() + "\" --up -z --camera 100,-30,6,30 --fit --frames 4 --save-image \"" +
                         saved.string() + "\" 2>&1");
    ASSERT_EQ(e.status, 0) << e.output;
    const renderer::Image fromEditor = renderer::readImage(saved);
    const std::filesystem::path image = dir / "render_fit.exr";
    ASSERT_EQ(splatlab("render \"" + headsq() + "\" --up -z --camera 100,-30,6,30 --fit --shading per-splat --size " +
                       std::to_string(fromEditor.width) + "x" + std::to_string(fromEditor.height) +
                       " --compositing sheet-front-to-back --frames 1 -o \"" + image.string() + "\"")
                  .status,
              0);
    const renderer::Image fromCli = renderer::readImage(image);
    ASSERT_EQ(fromCli.rgba.size(), fromEditor.rgba.size());
    const auto d = testing_support::renderDifference(fromCli, fromEditor);
    EXPECT_LE(d.elsewhere, 1e-5f);
    EXPECT_LE(d.atOpaque, 2e-3f);
    EXPECT_GT(coveredBox(fromEditor).y1 - coveredBox(fromEditor).y0, int(0.85 * fromEditor.height));
}

TEST(Cli, TheEditorWithoutAVolumeOpensTheBundledBonsaiFramedInItsPresetAndLit) {
    // The first picture a newcomer sees (scripts/editor): the defaults main.cpp gives the bundled bonsai are
    // the view `render` draws with these flags.
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path dir = testing_support::testOutputDir(), saved = dir / "editor_default.exr",
                                drawn = dir / "render_default.exr";
    const CliRun e = runShell("LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE
                         "\" editor --frames 4 --save-image \"" + saved.string() + "\" 2>&1");
    ASSERT_EQ(e.status, 0) << e.output;
    const renderer::Image fromEditor = renderer::readImage(saved);
    const std::string bonsai = (testing_support::assetDir() / "volumes" / "bonsai.nhdr").string();
    const CliRun r = splatlab("render \"" + bonsai + "\" --tf bonsai --up y --camera 30,20,2.5,30 --fit --shading "
                              "per-splat --density 2 --size " + std::to_string(fromEditor.width) + "x" +
                              std::to_string(fromEditor.height) + " --frames 1 -o \"" + drawn.string() + "\"");
    ASSERT_EQ(r.status, 0) << r.output;
    const renderer::Image fromCli = renderer::readImage(drawn);
    ASSERT_EQ(fromCli.rgba.size(), fromEditor.rgba.size());
    const auto d = testing_support::renderDifference(fromCli, fromEditor);
    EXPECT_LE(d.elsewhere, 1e-5f);
    EXPECT_LE(d.atOpaque, 2e-3f);
    EXPECT_GT(coveredBox(fromEditor).y1 - coveredBox(fromEditor).y0, int(0.6 * fromEditor.height))
        << "framed, the bonsai fills most of the height";
}

// Settings > Image-aligned slabs on (from a session): the still view ends in slabs, and Save image writes
// them, as `render --session` draws the same view (and `--image-slabs 0` the session's sheets).
TEST(Cli, TheEditorEndsAStillViewInSlabsAndSavesThemAsRenderDrawsThem) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path dir = testing_support::testOutputDir();
    const std::filesystem::path session = dir / "slab_session.json", saved = dir / "editor_slabs.exr",
                                slabs = dir / "render_slabs.exr", sheets = dir / "render_sheets.exr";
    std::ofstream(session) << nlohmann::json{
        {"splatlab_session", 1},
        {"volume", headsq()},
        {"camera", {{"azimuth", 60}, {"elevation", 15}, {"distance", 2.5}, {"fov", 30}, {"up", {0, 0, -1}}}},
        {"slabs", {{"enabled", true}, {"thickness", 1.0}, {"post_classified", false}}}};
    std::filesystem::remove(saved);
    const CliRun e = runShell("LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE
                              "\" editor --session \"" + session.string() + "\" --size 1280x800 --frames 4 --save-image \"" +
                              saved.string() + "\" 2>&1");
    ASSERT_EQ(e.status, 0) << e.output;
    EXPECT_THAT(e.output, HasSubstr("(image-aligned slabs)")) << "the note of what was saved";
    const renderer::Image fromEditor = renderer::readImage(saved);
    const std::string size = " --size " + std::to_string(fromEditor.width) + "x" + std::to_string(fromEditor.height);
    for (const auto& [out, flags] : {std::pair{slabs, ""}, std::pair{sheets, " --image-slabs 0"}}) {
        const CliRun r = splatlab("render --session \"" + session.string() + "\"" + size + flags +
                                  " --frames 1 -o \"" + out.string() + "\"");
        ASSERT_EQ(r.status, 0) << r.output;
        EXPECT_EQ(r.output.find("image-aligned slabs 1 voxels thick") != std::string::npos, out == slabs) << r.output;
    }
    const CliRun heat = splatlab("render --session \"" + session.string() + "\" --heatmap \"" +
                                 (dir / "slab_heat.png").string() + "\" -o \"" + (dir / "slab.png").string() + "\"");
    EXPECT_NE(heat.status, 0);
    EXPECT_THAT(heat.output, HasSubstr("the session's image-aligned slabs draw no heatmap (--image-slabs 0"));
    const renderer::Image fromCli = renderer::readImage(slabs);
    ASSERT_EQ(fromCli.rgba.size(), fromEditor.rgba.size());
    EXPECT_GT(renderer::imageStats(fromEditor).coveredFraction, 0.1);
    const auto d = testing_support::renderDifference(fromCli, fromEditor);
    EXPECT_LE(d.elsewhere, 1e-5f) << "see editor_slabs.exr and render_slabs.exr";
    EXPECT_LE(d.atOpaque, 2e-3f) << "see editor_slabs.exr and render_slabs.exr";
    const auto fromSheets = testing_support::renderDifference(renderer::readImage(sheets), fromEditor);
    EXPECT_GT(std::max(fromSheets.elsewhere, fromSheets.atOpaque), 0.02f) << "the saved view is the sheets'";
}
