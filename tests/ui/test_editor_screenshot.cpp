// ui layer, end to end: the real editor runs under Xvfb (Mesa llvmpipe) and writes a screenshot; the
// test checks that the viewport shows the volume and that the panels look unlike the viewport. It
// compares regions with each other, never with a stored image.
#include "editor_window.h"
#include "image_compare.h"
#include "renderer/io/image.h"
#include "renderer/model/procedural.h"
#include "test_paths.h"
#include "ui/dock_layout.h"
#include "ui/session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

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

// The editor's dock space in its 1280x800 window (editor_window.h).
using testing_support::kMenuBarPx;
const ui::Rect kDockArea = testing_support::kEditorDockArea;

ui::Rect shrink(const ui::Rect& r, float top, float fraction) {
    const ui::Rect body{r.x, r.y + top, r.w, r.h - top};
    return {body.x + body.w * fraction, body.y + body.h * fraction, body.w * (1 - 2 * fraction),
            body.h * (1 - 2 * fraction)};
}

// Runs the editor on the bundled headsq under Xvfb with `flags`, writes a 1280x800 screenshot to
// test_out/<name> and returns it. Leak checking is off for the child only: Mesa and libX11 leak from
// a driver module they have already unloaded, which no suppression can name (a bare GLFW window
// leaks 5 KB the same way).
renderer::Image editorScreenshot(const std::string& flags, const std::string& name, bool withVolume = true,
                                 std::filesystem::path volume = testing_support::assetDir() / "volumes" / "headsq.nhdr") {
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

double meanDifference(const renderer::Image& a, const renderer::Image& b, const ui::Rect& r) {
    double sum = 0.0;
    for (int y = int(r.y); y < int(r.bottom()); ++y)
        for (int x = int(r.x); x < int(r.right()); ++x)
            for (int c = 0; c < 3; ++c) sum += std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c]);
    return sum / (3.0 * r.w * r.h);
}

// 162^3 voxels of concentric shells, just over the 2^22 from which the editor previews, as uint8 NRRD.
std::filesystem::path largeVolume() {
    const std::filesystem::path dir = testing_support::testOutputDir("large_volume"), nhdr = dir / "shells.nhdr";
    const renderer::Volume v = renderer::makeSphereShells(162, 40.0, 12.0);
    std::string bytes(v.values.size(), '\0');
    for (size_t i = 0; i < v.values.size(); ++i) bytes[i] = char(std::lround(255.0f * std::clamp(v.values[i], 0.0f, 1.0f)));
    std::ofstream(dir / "shells.raw", std::ios::binary) << bytes;
    std::ofstream(nhdr) << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 162 162 162\nspacings: 1 1 1\n"
                           "encoding: raw\ndata file: shells.raw\n";
    return nhdr;
}

} // namespace

TEST(EditorScreenshot, LargeVolumesPreviewAtHalfResolutionWhileMovingAndSaveTheFullView) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    // --preview shows what a drag shows. Scripted runs never see a drag, so without it they show the
    // full render, and a volume under 2^22 voxels (headsq) has no preview at all.
    const std::filesystem::path large = largeVolume();
    const std::string view = "--camera 30,20,4,30 --tf grey-ramp ";
    const renderer::Image full = editorScreenshot(view, "editor_large.png", true, large);
    const renderer::Image preview = editorScreenshot(view + "--preview", "editor_large_preview.png", true, large);
    const renderer::Image small = editorScreenshot("--preview", "editor_small_preview.png");
    const renderer::Image smallFull = editorScreenshot("", "editor_small.png");
    ASSERT_FALSE(::testing::Test::HasFailure());
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::DockRects rects = ui::computeDockRects(layout, kDockArea);
    const ui::Rect viewport = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.0f);
    const ui::Rect centre = shrink(rects.node[size_t(layout.find("viewport"))], 30.0f, 0.25f);
    const ui::Rect note{viewport.x, viewport.y, 400.0f, 20.0f};   // the preview's line at the top left

    // The preview is the same view at half resolution: its own pixels (the shells' edges blur), yet close
    // on average (measured: largest 0.50, mean 0.039, all at the blurred edges). Its extinction is
    // checked exactly by HalfResolution.WithDensityForItRendersTheVolumesExtinction.
    const double largest = largestDifference(full, preview, centre), mean = meanDifference(full, preview, centre);
    std::printf("[ editor   ] preview against the full render: largest %.3f, mean %.4f\n", largest, mean);
    EXPECT_GT(largest, 0.1) << "the preview was not drawn, see editor_large_preview.png";
    EXPECT_LT(mean, 0.06) << "the preview is not the same view, see editor_large_preview.png";
    const double background = modalLuminance(full, viewport);
    EXPECT_GT(fractionBrighterThan(preview, note, background + 0.15), 0.01) << "no preview note";
    EXPECT_EQ(fractionBrighterThan(full, note, background + 0.15), 0.0);
    EXPECT_LE(largestDifference(small, smallFull, viewport), 1.0 / 255.0) << "headsq has no preview";

    // Save image writes the full view even while the preview is shown: what `render` draws.
    const std::filesystem::path saved = testing_support::testOutputDir() / "editor_large_preview_saved.exr",
                                rendered = testing_support::testOutputDir() / "render_large.exr";
    const std::string editor = "LIBGL_ALWAYS_SOFTWARE=1 ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" xvfb-run -a -s "
                               "\"-screen 0 1280x800x24\" \"" SPLATLAB_EXE "\" editor \"" + large.string() + "\" " + view +
                               "--preview --size 1280x800 --frames 3 --save-image \"" + saved.string() + "\"";
    ASSERT_EQ(std::system(editor.c_str()), 0) << editor;
    const renderer::Image fromEditor = renderer::readImage(saved);
    const std::string render = "LIBGL_ALWAYS_SOFTWARE=1 \"" SPLATLAB_EXE "\" render \"" + large.string() + "\" " + view +
                               "--frames 1 --size " + std::to_string(fromEditor.width) + "x" +
                               std::to_string(fromEditor.height) + " -o \"" + rendered.string() + "\" > /dev/null";
    ASSERT_EQ(std::system(render.c_str()), 0) << render;
    const auto d = testing_support::renderDifference(renderer::readImage(rendered), fromEditor);
    EXPECT_LE(d.elsewhere, 1e-5f);
    EXPECT_LE(d.atOpaque, 2e-3f);
}

// A far view rests on a coarser level (Settings > Inspect > Coarser levels far away, on by default): the
// line at the viewport's top left says so, and the level shows the volume; close up, no line.
TEST(EditorScreenshot, AFarViewOfALargeVolumeRestsOnACoarserLevelAndSaysSo) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path large = largeVolume();
    const renderer::Image far = editorScreenshot("--camera 30,20,40,30 --tf grey-ramp", "editor_far_level.png", true, large);
    const renderer::Image close = editorScreenshot("--camera 30,20,4,30 --tf grey-ramp", "editor_close_level.png", true, large);
    ASSERT_FALSE(::testing::Test::HasFailure());
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::Rect viewport = shrink(ui::computeDockRects(layout, kDockArea).node[size_t(layout.find("viewport"))], 30.0f, 0.0f);
    const ui::Rect note{viewport.x, viewport.y, 400.0f, 20.0f};
    const ui::Rect centre = shrink(viewport, 0.0f, 0.45f);   // the volume, a few pixels across at 40 radii
    const double background = modalLuminance(far, viewport);
    EXPECT_GT(fractionBrighterThan(far, note, background + 0.15), 0.01) << "no far-view note, see editor_far_level.png";
    EXPECT_EQ(fractionBrighterThan(close, note, background + 0.15), 0.0) << "see editor_close_level.png";
    EXPECT_GT(fractionBrighterThan(far, centre, background + 0.1), 0.05) << "the level shows no volume";
}

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
    const ui::DockRects rects = ui::computeDockRects(layout, kDockArea);
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
    const ui::DockRects rects = ui::computeDockRects(layout, kDockArea);
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

TEST(EditorScreenshot, HeatmapOverlayAtOpacityZeroIsTheImageAtOneTheHeatmapAndBetweenTheirBlend) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    // Near enough that headsq takes reconstruction in front and EWA behind: the heatmap has two colours.
    const std::string view = "--up -z --filter adaptive --camera 30,20,1.6,30 ";
    const std::filesystem::path saved = testing_support::testOutputDir() / "editor_overlay_heatmap_saved.png";
    const renderer::Image plain = editorScreenshot(view, "editor_overlay_plain.png");
    const renderer::Image zero = editorScreenshot(view + "--heatmap --heatmap-opacity 0", "editor_overlay_0.png");
    const renderer::Image half = editorScreenshot(view + "--heatmap --heatmap-opacity 0.5", "editor_overlay_05.png");
    // At 1 with Save image, which writes the heatmap alone there (renderer::writeImage over the background).
    const renderer::Image one = editorScreenshot(
        view + "--heatmap --heatmap-opacity 1 --save-image \"" + saved.string() + "\"", "editor_overlay_1.png");
    ASSERT_FALSE(::testing::Test::HasFailure());
    const renderer::Image heatmap = renderer::readImage(saved);
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::Rect node = ui::computeDockRects(layout, kDockArea).node[size_t(layout.find("viewport"))];
    // The render fills the viewport below its tab bar; compare above the legend (bottom-left, under 130 px).
    const ui::Rect image{node.x, node.bottom() - float(heatmap.height), float(heatmap.width), float(heatmap.height)};
    const ui::Rect above{image.x, image.y, image.w, image.h - 130.0f};
    ASSERT_EQ(int(image.w), int(node.w));
    // 0: the image alone (the heatmap is not drawn), as without the heatmap. 1/255: a render with the
    // heatmap's target on runs another shader variant, whose image may differ by 8-bit rounding (measured
    // on llvmpipe: one pixel, by 1/255).
    EXPECT_LE(largestDifference(plain, zero, above), 1.0 / 255.0 + 1e-6) << "see editor_overlay_0.png";
    // 1: the heatmap, as Save image writes it; 1/255: the one float rounded to 8 bits by GL and by the writer.
    double worst = 0.0;
    for (int y = 0; y < int(above.h); ++y)
        for (int x = 0; x < int(above.w); ++x)
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, double(std::abs(one.pixel(int(above.x) + x, int(above.y) + y)[c] -
                                                        heatmap.pixel(x, y)[c])));
    EXPECT_LE(worst, 1.0 / 255.0 + 1e-6) << "see editor_overlay_1.png";
    EXPECT_GT(largestDifference(plain, one, above), 0.3) << "the heatmap is not the image";
    // 0.5: the heatmap at alpha 128/255 over the image, each channel within 2/255 of the two's mean
    // (the alpha is 0.502, not 0.5, and the result is rounded to 8 bits).
    double blendWorst = 0.0;
    for (int y = int(above.y); y < int(above.bottom()); ++y)
        for (int x = int(above.x); x < int(above.right()); ++x)
            for (int c = 0; c < 3; ++c)
                blendWorst = std::max(blendWorst, double(std::abs(half.pixel(x, y)[c] -
                                                                  0.5f * (plain.pixel(x, y)[c] + one.pixel(x, y)[c]))));
    EXPECT_LE(blendWorst, 2.0 / 255.0) << "see editor_overlay_05.png";
    // The legend, bottom-left, is text over a dark box: present with the heatmap, absent without.
    const ui::Rect legend{image.x + 10.0f, image.bottom() - 100.0f, 200.0f, 90.0f};
    EXPECT_GT(largestDifference(zero, plain, legend), 0.3) << "no legend at opacity 0";
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
    const ui::DockRects rects = ui::computeDockRects(layout, kDockArea);
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
    const ui::DockRects rects = ui::computeDockRects(layout, kDockArea);
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
    const ui::DockRects rects = ui::computeDockRects(layout, kDockArea);
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
