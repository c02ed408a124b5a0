// ui layer, end to end: the real editor runs under Xvfb (Mesa llvmpipe) and writes a screenshot; the
// test checks that the viewport shows the volume and that the panels look unlike the viewport. It
// compares regions with each other, never with a stored image.
#include "renderer/image.h"
#include "test_paths.h"
#include "ui/dock_layout.h"
#include "ui/session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace {

double luminance(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

// The most common 8-bit luminance in `r`: a flat background wins over the shaded volume and text.
double modalLuminance(const renderer::Image& image, const ui::Rect& r) {
    std::array<int, 256> counts{};
    for (int y = int(r.y); y < int(r.bottom()); ++y)
        for (int x = int(r.x); x < int(r.right()); ++x)
            ++counts[size_t(std::lround(luminance(image.pixel(x, y)) * 255.0))];
    return double(std::max_element(counts.begin(), counts.end()) - counts.begin()) / 255.0;
}

double fractionBrighterThan(const renderer::Image& image, const ui::Rect& r, double threshold) {
    size_t bright = 0, all = 0;
    for (int y = int(r.y); y < int(r.bottom()); ++y)
        for (int x = int(r.x); x < int(r.right()); ++x, ++all)
            bright += luminance(image.pixel(x, y)) > threshold;
    return all ? double(bright) / double(all) : 0.0;
}

// The largest difference of any colour channel between two screenshots inside `r`.
double largestDifference(const renderer::Image& a, const renderer::Image& b, const ui::Rect& r) {
    double worst = 0.0;
    for (int y = int(r.y); y < int(r.bottom()); ++y)
        for (int x = int(r.x); x < int(r.right()); ++x)
            for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c])));
    return worst;
}

ui::Rect shrink(const ui::Rect& r, float top, float fraction) {
    const ui::Rect body{r.x, r.y + top, r.w, r.h - top};
    return {body.x + body.w * fraction, body.y + body.h * fraction, body.w * (1 - 2 * fraction),
            body.h * (1 - 2 * fraction)};
}

// Runs the editor on the bundled headsq under Xvfb with `flags`, writes a 1280x800 screenshot to
// test_out/<name> and returns it. Leak checking is off for the child only: Mesa and libX11 leak from
// a driver module they have already unloaded, which no suppression can name (a bare GLFW window
// leaks 5 KB the same way).
renderer::Image editorScreenshot(const std::string& flags, const std::string& name, bool withVolume = true) {
    const std::filesystem::path volume = testing_support::assetDir() / "volumes" / "headsq.nhdr";
    EXPECT_TRUE(std::filesystem::exists(volume)) << volume << " is missing from the bundled assets";
    const std::filesystem::path shot = testing_support::testOutputDir() / name;
    std::filesystem::remove(shot);
    const std::string command = "LIBGL_ALWAYS_SOFTWARE=1 ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" "
                                "xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE "\" editor " +
                                (withVolume ? "\"" + volume.string() + "\" " : std::string()) + flags +
                                " --screenshot \"" + shot.string() +
                                "\" --frames 5 --size 1280x800";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    return renderer::readImage(shot);
}

} // namespace

TEST(EditorScreenshot, ViewportShowsTheVolumeAndPanelsDifferFromIt) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::string shot = "editor.png";
    const renderer::Image image = editorScreenshot("", shot);
    ASSERT_FALSE(::testing::Test::HasFailure());
    ASSERT_EQ(image.width, 1280);
    ASSERT_EQ(image.height, 800);

    // Regions come from the editor's own layout at this window size. 30 px skips the tab bars.
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::DockRects rects = ui::computeDockRects(layout, {0, 0, 1280, 800});
    const ui::Rect viewport = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.0f);
    const ui::Rect centre = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.25f);
    const ui::Rect left = shrink(rects.node[size_t(layout.find("left"))], 30.0f, 0.0f);

    // 1. The viewport's centre half shows the volume: most of it clearly above the background
    //    (measured 0.90 on llvmpipe; an empty or misplaced image leaves it near 0).
    //    0.08 is about 20 grey levels, far above the 8-bit rounding of the flat background.
    const double background = modalLuminance(image, viewport);
    const double covered = fractionBrighterThan(image, centre, background + 0.08);
    std::printf("[ editor   ] viewport centre covered by the volume: %.3f\n", covered);
    EXPECT_GT(covered, 0.5) << "viewport background " << background << ", see " << shot;

    // 2. The settings panel is not more viewport: another flat colour, and text on it.
    EXPECT_GT(std::abs(modalLuminance(image, left) - background), 2.0 / 255.0) << "see " << shot;
    EXPECT_GT(fractionBrighterThan(image, left, 0.5), 0.002) << "no text in the settings panel, see " << shot;
}

TEST(EditorScreenshot, HeatmapViewShowsFilterColoursInsteadOfTheVolume) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    // Full EWA everywhere: the heatmap is pure blue where the volume is (no red, no green).
    const std::string shot = "editor_heatmap.png";
    const renderer::Image image = editorScreenshot("--filter ewa --heatmap", shot);
    ASSERT_FALSE(::testing::Test::HasFailure());
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::DockRects rects = ui::computeDockRects(layout, {0, 0, 1280, 800});
    const ui::Rect centre = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.25f);
    size_t blue = 0, other = 0;
    for (int y = int(centre.y); y < int(centre.bottom()); ++y)
        for (int x = int(centre.x); x < int(centre.right()); ++x) {
            const auto p = image.pixel(x, y);
            if (p[2] > 0.3f && p[0] < 0.1f && p[1] < 0.1f) ++blue;
            else if (p[0] > 0.3f || p[1] > 0.3f) ++other;
        }
    EXPECT_GT(blue, 10u * (other + 1)) << "see " << shot;
    EXPECT_GT(double(blue) / (double(centre.w) * centre.h), 0.3) << "see " << shot;
}

TEST(EditorScreenshot, TiledSheetsShowTheSameViewportAsRasterisedSheets) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    // Sheets start tiled (compute passes); the same frame through the rasteriser must match to 8-bit
    // rounding in the viewport (the Stats text below it differs).
    const renderer::Image raster =
        editorScreenshot("--compositing sheet-front-to-back --primitive raster", "editor_sheets.png");
    const renderer::Image tiled = editorScreenshot("--compositing sheet-front-to-back", "editor_tiles.png");
    ASSERT_FALSE(::testing::Test::HasFailure());
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::DockRects rects = ui::computeDockRects(layout, {0, 0, 1280, 800});
    const ui::Rect viewport = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.0f);
    const ui::Rect centre = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.25f);
    EXPECT_LE(largestDifference(raster, tiled, viewport), 1.5 / 255.0) << "see editor_sheets.png and editor_tiles.png";
    EXPECT_GT(fractionBrighterThan(tiled, centre, modalLuminance(tiled, viewport) + 0.08), 0.5) << "see editor_tiles.png";
}

TEST(EditorScreenshot, ASessionOpensTheViewTheFlagsItStandsForWouldOpen) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    // The session names the volume, TF, camera and compositing; the editor opens it with no other flag.
    ui::EditorState state;
    state.tf = renderer::builtinPreset("fire");
    state.camera.azimuthDeg = 200.0;
    state.camera.elevationDeg = 10.0;
    state.camera.distance = 2.2;
    state.camera.fovYDeg = 40.0;
    state.camera.up = {0.0, 0.0, -1.0};
    state.settings.compositing = renderer::Compositing::SheetFrontToBack;
    const auto session = testing_support::testOutputDir("session") / "editor_session.json";
    ui::saveSession(state, testing_support::assetDir() / "volumes" / "headsq.nhdr", session);
    const renderer::Image opened =
        editorScreenshot("--session \"" + session.string() + "\"", "editor_session.png", false);
    const renderer::Image flags = editorScreenshot(
        "--tf fire --camera 200,10,2.2,40 --up -z --compositing sheet-front-to-back", "editor_session_flags.png");
    ASSERT_FALSE(::testing::Test::HasFailure());
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::DockRects rects = ui::computeDockRects(layout, {0, 0, 1280, 800});
    const ui::Rect viewport = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.0f);
    const ui::Rect centre = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.25f);
    EXPECT_LE(largestDifference(opened, flags, viewport), 1.5 / 255.0) << "see editor_session.png and editor_session_flags.png";
    EXPECT_GT(fractionBrighterThan(opened, centre, modalLuminance(opened, viewport) + 0.08), 0.3)
        << "see editor_session.png";
}

TEST(EditorScreenshot, SpinTurnsTheCameraAtItsSpeedAndThePerformanceChartFillsIn) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    // Scripted runs turn by 1/60 s a frame: 5 frames at 90 degrees a second add 7.5 degrees of azimuth.
    const renderer::Image spun =
        editorScreenshot("--camera 30,15,2.5,30 --up -z --spin 90 --tab Performance", "editor_spin.png");
    const renderer::Image turned = editorScreenshot("--camera 37.5,15,2.5,30 --up -z", "editor_spin_flags.png");
    const renderer::Image still = editorScreenshot("--camera 30,15,2.5,30 --up -z", "editor_still.png");
    ASSERT_FALSE(::testing::Test::HasFailure());
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::DockRects rects = ui::computeDockRects(layout, {0, 0, 1280, 800});
    const ui::Rect viewport = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.0f);
    EXPECT_LE(largestDifference(spun, turned, viewport), 1.5 / 255.0) << "see editor_spin.png, editor_spin_flags.png";
    EXPECT_GT(largestDifference(spun, still, viewport), 0.2) << "the spin did not turn the view (editor_still.png)";
    // The chart (the bottom strip's right part) holds the pass colours of the renders timed so far.
    const ui::Rect bottom = rects.node[size_t(layout.find("bottom"))];
    const ui::Rect chart{bottom.x + bottom.w * 0.5f, bottom.y + 30.0f, bottom.w * 0.5f, bottom.h - 30.0f};
    size_t coloured = 0;
    for (int y = int(chart.y); y < int(chart.bottom()); ++y)
        for (int x = int(chart.x); x < int(chart.right()); ++x) {
            const float* p = spun.pixel(x, y);
            coloured += std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 0.3f;
        }
    EXPECT_GT(coloured, 20u) << "no pass colours in the Performance chart (editor_spin.png)";
}
