// ui layer, end to end: the editor under Xvfb with --split (two or four filters) and --split-difference
// (|A - B| or |A - truth|). Save image writes the panes in their layout; each pane is what `splatlab render`
// draws at the pane's size with that pane's filter, |A - B|'s RMSE is renderer::compareImages of two such
// renders, |A - truth|'s that of pane A against `splatlab reference`, and the viewport shows the panes it
// saves.
#include "editor_window.h"
#include "image_compare.h"
#include "renderer/io/image.h"
#include "renderer/math/metrics.h"
#include "shell_run.h"
#include "test_paths.h"
#include "ui/dock_layout.h"
#include "ui/panels.h"
#include "ui/split_view.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <tuple>
#include <utility>

namespace {

// The command's output, and its exit code in `status`.
std::string runCapturing(const std::string& command, int& status) {
    testing_support::ShellRun r = testing_support::runShell(command);
    status = r.status;
    return std::move(r.output);
}

renderer::Image crop(const renderer::Image& image, int x0, int width) {
    renderer::Image out(width, image.height);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 4; ++c)
                out.pixel(x, y)[c] = image.pixel(x0 + x, y)[c];
    return out;
}

} // namespace

TEST(EditorSplit, ASplitThatIsNotTwoOrFourFiltersIsRefusedNamingTheFlag) {
    const std::pair<const char*, const char*> bad[] = {
        {"--split ewa",
         "--split: expected two or four filters, FILTER_A,FILTER_B or FILTER_A,FILTER_B,FILTER_C,"
         "FILTER_D, got 'ewa' (1 names)"},
        {"--split ewa,low-pass,adaptive", "got 'ewa,low-pass,adaptive' (3 names)"},
        {"--split ewa,low-pass,adaptive,ewa,ewa", "(5 names)"},
        {"--split ewa,,low-pass,adaptive", "--split: unknown filter ''"},
        {"--split ewa,sharp",
         "--split: unknown filter 'sharp' (known: reconstruction, low-pass, ewa, adaptive)"},
        {"--split-difference", "--split-difference: needs --split A,B (or A,B,C,D)"},
        {"--split ewa,low-pass --split-difference c",
         "--split-difference: expected nothing (|A - B|) or 'truth' (|A - ground truth|), got 'c'"},
    };
    for (const auto& [flags, expected] : bad) {
        int status = -1; // refused before a window opens: no display needed
        const std::string output = runCapturing(
            "env -u DISPLAY \"" SPLATLAB_EXE "\" editor " + std::string(flags) + " 2>&1", status);
        EXPECT_NE(status, 0) << flags;
        EXPECT_NE(output.find(expected), std::string::npos) << flags << "\n" << output;
    }
}

// --split with four names opens four panes in a 2 x 2 grid: Save image writes them in that layout, each
// what `splatlab render` draws at the pane's size with that pane's filter; the session the editor closes
// with keeps the four, and opening it shows the same four panes again.
TEST(EditorSplit, FourFiltersOpenFourPanesEachItsFiltersRenderAndTheSessionKeepsThem) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::string volume = (testing_support::assetDir() / "volumes" / "headsq.nhdr").string();
    const std::filesystem::path out = testing_support::testOutputDir("editor_split_four");
    const std::filesystem::path saved = out / "four.exr", session = out / "four.json",
                                again = out / "again.exr";
    const std::string view = "--up -z --camera 30,20,2.5,30 --compositing sheet-back-to-front --shading none ";
    const std::string xvfb =
        "LIBGL_ALWAYS_SOFTWARE=1 ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" xvfb-run -a -s "
        "\"-screen 0 1280x800x24\" \"" SPLATLAB_EXE "\" editor ";
    int status = -1;
    const std::string editor = xvfb + "\"" + volume + "\" " + view +
                               "--split reconstruction,low-pass,ewa,adaptive --size 1280x800 --frames 3 "
                               "--save-image \"" +
                               saved.string() + "\" --session-out \"" + session.string() + "\"";
    std::string printed = runCapturing(editor, status);
    ASSERT_EQ(status, 0) << editor << "\n" << printed;
    EXPECT_NE(
        printed.find("(split: A reconstruction, sheet-back-to-front | B low-pass, sheet-back-to-front | "
                     "C ewa, sheet-back-to-front | D adaptive, sheet-back-to-front)"),
        std::string::npos)
        << printed;

    const renderer::Image panes = renderer::readImage(saved);
    ASSERT_EQ(panes.width % 2, 0);
    ASSERT_EQ(panes.height % 2, 0);
    const int width = panes.width / 2, height = panes.height / 2;
    const char* filters[] = {"reconstruction", "low-pass", "ewa", "adaptive"};
    for (int i = 0; i < 4; ++i) {
        const std::filesystem::path file = out / (std::string("render_") + filters[i] + ".exr");
        const std::string command = "env -u DISPLAY LIBGL_ALWAYS_SOFTWARE=1 \"" SPLATLAB_EXE "\" render \"" +
                                    volume + "\" " + view + "--filter " + filters[i] + " --frames 1 --size " +
                                    std::to_string(width) + "x" + std::to_string(height) + " -o \"" +
                                    file.string() + "\" > /dev/null";
        ASSERT_EQ(std::system(command.c_str()), 0) << command;
        const renderer::Image alone = renderer::readImage(file);
        renderer::Image pane(width, height); // A B over C D
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                for (int c = 0; c < 4; ++c)
                    pane.pixel(x, y)[c] = panes.pixel((i % 2) * width + x, (i / 2) * height + y)[c];
        const auto d = testing_support::renderDifference(alone, pane);
        EXPECT_LE(d.elsewhere, 1e-5f) << "pane "
                                      << "ABCD"[i] << " (" << filters[i] << ")";
        EXPECT_LE(d.atOpaque, 2e-3f) << "pane "
                                     << "ABCD"[i] << " (" << filters[i] << ")";
    }

    std::ifstream in(session);
    ASSERT_TRUE(in) << "no session written";
    const nlohmann::json json = nlohmann::json::parse(in);
    EXPECT_EQ(json["split"]["panes"], 4);
    for (int i = 0; i < 4; ++i)
        EXPECT_EQ(json["split"][std::string("filter_") + "abcd"[i]], filters[i]);
    EXPECT_EQ(json["split"]["difference"], "off");
    // The session opens the same four panes: the same image.
    const std::string reopen = xvfb + "--session \"" + session.string() +
                               "\" --size 1280x800 --frames 3 "
                               "--save-image \"" +
                               again.string() + "\"";
    printed = runCapturing(reopen, status);
    ASSERT_EQ(status, 0) << reopen << "\n" << printed;
    const renderer::Image reopened = renderer::readImage(again);
    ASSERT_EQ(reopened.width, panes.width);
    ASSERT_EQ(reopened.height, panes.height);
    EXPECT_LE(testing_support::renderDifference(panes, reopened).elsewhere, 1e-5f);
}

// --split-difference truth: the difference pane is pane A against the ground truth of the view at the
// pane's size, the one `splatlab reference` computes for the same session and size (far-away, a volume a
// few pixels across: a truth of seconds). Scripted runs wait for the full truth.
TEST(EditorSplit, TheTruthDifferenceIsPaneAAgainstTheGroundTruthOfItsView) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path out = testing_support::testOutputDir("editor_split_truth");
    const std::filesystem::path saved = out / "truth.exr", session = out / "truth.json",
                                cache = out / "cache", reference = out / "reference.exr";
    std::filesystem::remove_all(cache); // the editor computes it
    int status = -1;
    const std::string editor =
        "SPLATLAB_CACHE_DIR=\"" + cache.string() +
        "\" LIBGL_ALWAYS_SOFTWARE=1 ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" xvfb-run -a -s "
        "\"-screen 0 1280x800x24\" \"" SPLATLAB_EXE "\" editor --scene far-away --split reconstruction,ewa "
        "--split-difference truth --size 1280x800 --frames 3 --save-image \"" +
        saved.string() + "\" --session-out \"" + session.string() + "\"";
    const std::string printed = runCapturing(editor, status);
    ASSERT_EQ(status, 0) << editor << "\n" << printed;
    const size_t at = printed.find("|A - truth| RMSE ");
    ASSERT_NE(at, std::string::npos) << "Save image names the truth difference's RMSE: " << printed;
    const double rmse = std::atof(printed.c_str() + at + 17);
    const renderer::Image panes = renderer::readImage(saved);
    ASSERT_EQ(panes.width % 3, 0);
    const int width = panes.width / 3, height = panes.height;
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    EXPECT_NE(printed.find("against the truth at " + size + ")"), std::string::npos)
        << "the full truth: " << printed;

    const std::string direct = "env -u DISPLAY \"" SPLATLAB_EXE "\" reference --session \"" +
                               session.string() + "\" --size " + size + " --no-cache -o \"" +
                               reference.string() + "\" > /dev/null 2>&1";
    ASSERT_EQ(std::system(direct.c_str()), 0) << direct;
    const renderer::ImageError metric =
        renderer::compareImages(crop(panes, 0, width), renderer::readImage(reference));
    EXPECT_GT(metric.rmse, 1e-4) << "reconstruction and the truth should differ at this view";
    EXPECT_NEAR(rmse, metric.rmse, 1e-3 * metric.rmse) << printed;
    std::printf("[ split    ] editor's |A - truth| RMSE %.6f, pane A against `reference`: %.6f (%.2f dB)\n",
                rmse, metric.rmse, metric.psnrDb);
}

TEST(EditorSplit, EachPaneIsItsFiltersRenderAndTheDifferenceRmseIsTheirMetric) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::string volume = (testing_support::assetDir() / "volumes" / "headsq.nhdr").string();
    const std::filesystem::path out = testing_support::testOutputDir(),
                                saved = out / "editor_split_saved.exr", shot = out / "editor_split.png";
    const std::string view = "--up -z --camera 30,20,2.5,30 --compositing sheet-front-to-back --shading none ";
    int status = -1;
    const std::string editor =
        "LIBGL_ALWAYS_SOFTWARE=1 ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" xvfb-run -a -s "
        "\"-screen 0 1280x800x24\" \"" SPLATLAB_EXE "\" editor \"" +
        volume + "\" " + view +
        "--split reconstruction,low-pass --split-difference --size 1280x800 --frames 5 "
        "--save-image \"" +
        saved.string() + "\" --screenshot \"" + shot.string() + "\"";
    const std::string printed = runCapturing(editor, status);
    ASSERT_EQ(status, 0) << editor << "\n" << printed;
    const size_t at = printed.find("RMSE ");
    ASSERT_NE(at, std::string::npos) << "Save image names the difference's RMSE: " << printed;
    const double rmse = std::atof(printed.c_str() + at + 5);

    const renderer::Image panes = renderer::readImage(saved);
    ASSERT_EQ(panes.width % 3, 0);
    const int width = panes.width / 3, height = panes.height;
    const auto render = [&](const char* filter, const char* name) {
        const std::filesystem::path file = out / name;
        const std::string command = "env -u DISPLAY LIBGL_ALWAYS_SOFTWARE=1 \"" SPLATLAB_EXE "\" render \"" +
                                    volume + "\" " + view + "--filter " + filter + " --frames 1 --size " +
                                    std::to_string(width) + "x" + std::to_string(height) + " -o \"" +
                                    file.string() + "\" > /dev/null";
        EXPECT_EQ(std::system(command.c_str()), 0) << command;
        return renderer::readImage(file);
    };
    const renderer::Image a = render("reconstruction", "split_render_a.exr"),
                          b = render("low-pass", "split_render_b.exr");
    ASSERT_FALSE(::testing::Test::HasFailure());
    // The tolerances the editor-against-render tests use (front to back: image_compare.h's renderDifference).
    for (const auto& [pane, expected, name] : {std::tuple{0, &a, "A"}, std::tuple{1, &b, "B"}}) {
        const auto d = testing_support::renderDifference(*expected, crop(panes, pane * width, width));
        EXPECT_LE(d.elsewhere, 1e-5f) << "pane " << name;
        EXPECT_LE(d.atOpaque, 2e-3f) << "pane " << name;
    }
    const renderer::ImageError metric = renderer::compareImages(a, b);
    EXPECT_GT(metric.rmse, 1e-3) << "reconstruction and low-pass should differ at this view";
    EXPECT_NEAR(rmse, metric.rmse, 1e-3 * metric.rmse) << printed;
    std::printf("[ split    ] editor's |A - B| RMSE %.6f, metric of the two renders %.6f (%.2f dB)\n", rmse,
                metric.rmse, metric.psnrDb);

    // The viewport shows the panes it saved: the left pane below its label, over the background.
    const renderer::Image screen = renderer::readImage(shot);
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::Rect node =
        ui::computeDockRects(layout, testing_support::kEditorDockArea).node[size_t(layout.find("viewport"))];
    const int x0 = int(node.x), y0 = int(node.bottom()) - height;
    const float background[3] = {0.055f, 0.060f, 0.075f};
    double worst = 0.0;
    for (int y = 40; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                const float* p = panes.pixel(x, y);
                const double over = std::clamp(double(p[c]) + (1.0 - p[3]) * background[c], 0.0, 1.0);
                worst = std::max(worst, std::abs(double(screen.pixel(x0 + x, y0 + y)[c]) - over));
            }
    EXPECT_LE(worst, 2.0 / 255.0 + 1e-6) << "the viewport's left pane is not the saved one, see " << shot;
}

// Synthetic input: a 100 px drag in the right pane turns the one camera both panes show by 30 degrees
// (kOrbitDegPerPx); afterwards the left pane shows what `render` draws from the turned camera with the left
// pane's filter, the middle pane the right pane's, and the session the editor closes with keeps the split.
TEST(EditorSplit, ADragInEitherPaneMovesTheOneCameraAndEachPaneShowsItsFilter) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1 && command -v xdotool > /dev/null 2>&1 && "
                    "command -v import > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run, xdotool or ImageMagick's import not found";
    const std::string volume = (testing_support::assetDir() / "volumes" / "headsq.nhdr").string();
    const std::filesystem::path out = testing_support::testOutputDir("editor_split_drag");
    std::filesystem::remove(out / "session.json");
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::Rect node =
        ui::computeDockRects(layout, testing_support::kEditorDockArea).node[size_t(layout.find("viewport"))];
    // The viewport's image: the node below its tab bar (the render's height is read from the screenshot).
    const int dragX = int(node.x + node.w * 0.45f), dragY = int(node.y + node.h * 0.5f);
    const std::string script = std::string(SPLATLAB_SOURCE_DIR) + "/tests/ui/scripts/split_drag.sh";
    const std::string command = "LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" +
                                script + "\" \"" SPLATLAB_EXE "\" \"" + volume + "\" \"" + out.string() +
                                "\" " + std::to_string(dragX) + " " + std::to_string(dragY) + " > \"" +
                                (out / "drive.log").string() + "\" 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0)
        << "see " << (out / "drive.log") << " and " << (out / "editor.log");
    std::ifstream in(out / "session.json");
    ASSERT_TRUE(in) << "no session written";
    const nlohmann::json session = nlohmann::json::parse(in);
    EXPECT_NEAR(session["camera"]["azimuth"].get<double>(), 40.0 - 100.0 * ui::kOrbitDegPerPx, 1e-9);
    EXPECT_EQ(session["split"]["enabled"], true);
    EXPECT_EQ(session["split"]["filter_a"], "reconstruction");
    EXPECT_EQ(session["split"]["filter_b"], "low-pass");
    EXPECT_EQ(session["split"]["difference"], "b");

    // The panes on screen against Save image of a scripted run started at the turned camera (the test above
    // holds each saved pane equal to `render`'s), below the panes' labels, over the background.
    const std::filesystem::path saved = out / "split_turned.exr";
    int status = -1;
    const std::string scripted =
        "LIBGL_ALWAYS_SOFTWARE=1 ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" xvfb-run -a -s \"-screen 0 "
        "1280x800x24\" "
        "\"" SPLATLAB_EXE "\" editor \"" +
        volume +
        "\" --up -z --camera 10,20,2.5,30 --compositing sheet-front-to-back "
        "--split reconstruction,low-pass --split-difference --size 1280x800 --frames 3 --save-image \"" +
        saved.string() + "\"";
    const std::string printed = runCapturing(scripted, status);
    ASSERT_EQ(status, 0) << scripted << "\n" << printed;
    const renderer::Image panes = renderer::readImage(saved),
                          screen = renderer::readImage(out / "split_drag.png");
    const int width = panes.width / 3, x0 = int(node.x), y0 = int(node.bottom()) - panes.height;
    const float background[3] = {0.055f, 0.060f, 0.075f};
    for (int pane = 0; pane < 2; ++pane) {
        double worst = 0.0;
        for (int y = 40; y < panes.height; ++y)
            for (int x = 2; x < width; ++x) // past the line between the panes
                for (int c = 0; c < 3; ++c) {
                    const float* p = panes.pixel(pane * width + x, y);
                    const double over = std::clamp(double(p[c]) + (1.0 - p[3]) * background[c], 0.0, 1.0);
                    worst = std::max(worst,
                                     std::abs(double(screen.pixel(x0 + pane * width + x, y0 + y)[c]) - over));
                }
        // 8-bit rounding twice, and early termination's refreshes (at most 1 - 0.998) between two runs.
        EXPECT_LE(worst, 2.0 / 255.0 + 2e-3)
            << "pane " << pane << " after the drag, see " << (out / "split_drag.png");
    }
}

// Synthetic input while the truth computes: with every truth delayed 6 s (a slow scan's), a drag in pane
// A moves the camera; 3 s later pane A shows the new view and the difference pane shows no difference at
// all (its note says the truth is computing) rather than the old view's; once the new view's truth is in,
// the difference is back. The difference pane's image is opaque (inferno's dark end where A matches the
// truth), the empty pane the viewport's background.
TEST(EditorSplit, ACameraMoveWhileTheTruthComputesShowsNoStaleDifference) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1 && command -v xdotool > /dev/null 2>&1 && "
                    "command -v import > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run, xdotool or ImageMagick's import not found";
    const std::filesystem::path out = testing_support::testOutputDir("editor_split_truth_move");
    std::filesystem::remove_all(out / "cache");
    std::filesystem::remove(out / "session.json");
    for (const char* shot : {"truth_before.png", "truth_moved.png", "truth_after.png"})
        std::filesystem::remove(out / shot);
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::Rect node =
        ui::computeDockRects(layout, testing_support::kEditorDockArea).node[size_t(layout.find("viewport"))];
    const int dragX = int(node.x + node.w * 0.15f), dragY = int(node.y + node.h * 0.5f);
    // The difference pane: the third of three columns, below its title, figures and note lines.
    const int paneWidth = int(node.w) / 3, x0 = int(node.x) + 2 * paneWidth + 8, x1 = x0 + paneWidth / 2;
    const int y0 = int(node.y) + 110, y1 = int(node.bottom()) - 30;
    const std::string patch = std::to_string(x1 - x0) + "x" + std::to_string(y1 - y0) + "+" +
                              std::to_string(x0) + "+" + std::to_string(y0);
    const std::string script = std::string(SPLATLAB_SOURCE_DIR) + "/tests/ui/scripts/split_truth_move.sh";
    const std::string command = "LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" +
                                script + "\" \"" SPLATLAB_EXE "\" \"" + out.string() + "\" " +
                                std::to_string(dragX) + " " + std::to_string(dragY) + " " + patch + " > \"" +
                                (out / "drive.log").string() + "\" 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0)
        << "see " << (out / "drive.log") << " and " << (out / "editor.log");
    std::ifstream in(out / "session.json");
    ASSERT_TRUE(in) << "no session written";
    const nlohmann::json session = nlohmann::json::parse(in);
    EXPECT_NE(session["camera"]["azimuth"].get<double>(), 30.0) << "the drag moved the camera";

    const auto share = [&](const char* file) { // of the patch's pixels, those that are the difference image's
        const renderer::Image shot = renderer::readImage(out / file);
        int image = 0, all = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x, ++all) {
                const float* p = shot.pixel(x, y);
                const bool background = std::abs(p[0] - 0.055f) < 0.01f && std::abs(p[1] - 0.060f) < 0.01f &&
                                        std::abs(p[2] - 0.075f) < 0.01f;
                image += background ? 0 : 1;
            }
        return double(image) / all;
    };
    EXPECT_GT(share("truth_before.png"), 0.95) << "the first view's difference is shown";
    EXPECT_LT(share("truth_moved.png"), 0.01) << "a stale difference is shown after the move";
    EXPECT_GT(share("truth_after.png"), 0.95) << "the moved view's difference is shown once its truth is in";
}
