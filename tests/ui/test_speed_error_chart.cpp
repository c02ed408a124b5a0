// Speed against error as a chart: the Filters panel's chart (and the page `splatlab report` writes) put
// each measurement where its figures say, mark the Pareto front renderer::paretoFront finds and ring
// the settings in force; the report refuses bad input with one clear line.
#include "cli_run.h"
#include "imgui_null.h"
#include "renderer/oracle/speed_error.h"
#include "ui/panels.h"
#include "ui/speed_error_chart.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <regex>

using ::testing::HasSubstr;
using testing_support::CliRun;
using testing_support::splatlab;

namespace {

// 16 settings with times and errors that need every digit: setting k at (7 + 3.1k ms, 20 + 1.7 (k mod 5) dB).
std::vector<renderer::FilterMeasurement> handMadePoints() {
    std::vector<renderer::FilterMeasurement> points;
    const std::vector<renderer::SplatSettings> settings = renderer::speedErrorSettings({});
    for (size_t k = 0; k < settings.size(); ++k) {
        renderer::FilterMeasurement m;
        m.filter = settings[k].filter;
        m.compositing = settings[k].compositing;
        m.frameMs = 7.0 + 3.1 * double(k);
        m.p10Ms = m.frameMs - 0.4 - 0.01 * double(k);
        m.p90Ms = m.frameMs + 1.3 + 0.07 * double(k);
        m.psnrDb = 20.0 + 1.7 * double(k % 5);
        m.rmse = std::pow(10.0, -m.psnrDb / 20.0);
        m.frames = 5;
        points.push_back(m);
    }
    return points;
}

// The value at pixel `px` of an axis that maps lo..hi onto a..b.
double valueAt(double px, double a, double b, double lo, double hi) {
    return lo + (px - a) / (b - a) * (hi - lo);
}

// What a chart shows agrees with the measurements it was drawn from, to `tolerancePx` pixels.
void expectChartShows(const ui::SpeedErrorChart& c, const std::vector<renderer::FilterMeasurement>& points,
                      const renderer::SplatSettings& current, double tolerancePx) {
    ASSERT_EQ(c.points.size(), points.size());
    const std::vector<bool> front = renderer::paretoFront(points);
    const double msPerPx = (c.timeMs.hi - c.timeMs.lo) / (c.right - c.left);
    const double dbPerPx = (c.psnrDb.hi - c.psnrDb.lo) / (c.bottom - c.top);
    for (size_t i = 0; i < points.size(); ++i) {
        const ui::ChartPoint& p = c.points[i];
        const renderer::FilterMeasurement& m = points[i];
        EXPECT_NEAR(valueAt(p.x, c.left, c.right, c.timeMs.lo, c.timeMs.hi), m.frameMs, tolerancePx * msPerPx)
            << i;
        EXPECT_NEAR(valueAt(p.xLo, c.left, c.right, c.timeMs.lo, c.timeMs.hi), m.p10Ms, tolerancePx * msPerPx)
            << i;
        EXPECT_NEAR(valueAt(p.xHi, c.left, c.right, c.timeMs.lo, c.timeMs.hi), m.p90Ms, tolerancePx * msPerPx)
            << i;
        EXPECT_NEAR(valueAt(p.y, c.bottom, c.top, c.psnrDb.lo, c.psnrDb.hi), m.psnrDb, tolerancePx * dbPerPx)
            << i;
        EXPECT_EQ(p.pareto, front[i]) << i;
        EXPECT_EQ(p.current, m.filter == current.filter && m.compositing == current.compositing) << i;
    }
    EXPECT_LE(c.timeMs.lo, 0.0);
}

} // namespace

TEST_F(ImGuiNull, TheFiltersPanelsChartPutsEachMeasurementWhereItsFiguresSay) {
    windowWidth = 955.0f, windowHeight = 260.0f; // the bottom strip of a 1280x800 window
    ui::EditorState state;
    state.settings.filter = renderer::FilterMode::Ewa;
    state.settings.compositing = renderer::Compositing::SheetFrontToBack;
    const renderer::ImagePlane plane =
        renderer::makeImagePlane(renderer::Camera{}, {32, 32, 46}, 60.0, 955, 545);
    ui::FiltersView view;
    view.plane = &plane;
    view.dims = {64, 64, 93};
    view.radius = 60.0;
    view.cropPx = 96;
    view.measurements = handMadePoints();
    ui::FiltersChanges changes;
    frame([&] { changes = ui::drawFiltersPanel(state, view); });
    ASSERT_TRUE(changes.chart) << "no chart drawn";
    const ui::SpeedErrorChart& c = *changes.chart;
    expectChartShows(c, view.measurements, state.settings, 1e-6);
    EXPECT_EQ(
        std::count_if(c.points.begin(), c.points.end(), [](const ui::ChartPoint& p) { return p.current; }),
        1);
    // The fronts here: of the attenuating modes (k = 0..11) the fastest point of each new best PSNR,
    // k = 0..4 (20, 21.7, .. 26.8 dB); of X-ray's (k = 12..15, its own truth) k = 12..14.
    EXPECT_EQ(c.front, (std::vector<size_t>{0, 1, 2, 3, 4, 12, 13, 14}));
    // Each marker is drawn there: a vertex of the draw list within its radius (0.3 font) of the point.
    const float r = 0.3f * ImGui::GetFontSize();
    const ImDrawData* data = ImGui::GetDrawData();
    for (size_t i = 0; i < c.points.size(); ++i) {
        bool drawn = false;
        for (int l = 0; l < data->CmdListsCount && !drawn; ++l)
            for (const ImDrawVert& v : data->CmdLists[l]->VtxBuffer)
                if (std::hypot(v.pos.x - c.points[i].x, v.pos.y - c.points[i].y) <= 1.6 * r) drawn = true;
        EXPECT_TRUE(drawn) << "no marker at point " << i;
    }
    // Inside the plot, and the window.
    EXPECT_GT(c.left, 0.0);
    EXPECT_LT(c.right, windowWidth);
    EXPECT_LT(c.bottom, windowHeight);
    for (const ui::ChartPoint& p : c.points) {
        EXPECT_GE(p.xLo, c.left);
        EXPECT_LE(p.xHi, c.right);
        EXPECT_GE(p.y, c.top);
        EXPECT_LE(p.y, c.bottom);
    }
}

TEST_F(ImGuiNull, TheSlabsInForceAreTheRingedPointAndPostClassifiedSlabsAFrontOfTheirOwn) {
    // Settings > Image-aligned slabs on: Measure's last point is the slabs in force (EWA, sheets front to back,
    // 0.5 voxels, post-classified), drawn as a hexagon and ringed; the sheets of the same filter are not.
    windowWidth = 955.0f, windowHeight = 260.0f;
    ui::EditorState state;
    state.settings.filter = renderer::FilterMode::Ewa;
    state.settings.compositing = renderer::Compositing::SheetFrontToBack;
    const renderer::ImagePlane plane = renderer::makeImagePlane(renderer::Camera{}, {32, 32, 46}, 60.0, 955, 545);
    ui::FiltersView view;
    view.plane = &plane;
    view.radius = 60.0;
    view.cropPx = 96;
    view.measurements = handMadePoints();
    renderer::FilterMeasurement slabs = view.measurements.front();
    slabs.filter = renderer::FilterMode::Ewa;
    slabs.compositing = renderer::Compositing::SheetFrontToBack;
    slabs.slabThickness = 0.5;
    slabs.postClassified = true;
    slabs.frameMs = 300.0, slabs.p10Ms = 290.0, slabs.p90Ms = 320.0, slabs.psnrDb = 19.0;
    view.measurements.push_back(slabs);
    view.slabsInForce = true;
    ui::FiltersChanges changes;
    frame([&] { changes = ui::drawFiltersPanel(state, view); });
    ASSERT_TRUE(changes.chart);
    const ui::SpeedErrorChart& c = *changes.chart;
    const size_t last = view.measurements.size() - 1;
    for (size_t i = 0; i < c.points.size(); ++i) EXPECT_EQ(c.points[i].current, i == last) << i;
    // Slowest and least accurate, yet on a front: the only point against the post-classified truth, last.
    EXPECT_TRUE(c.points[last].pareto);
    EXPECT_EQ(c.front.back(), last);
    EXPECT_EQ(ui::pointStyle(slabs).shape, ui::PointStyle::Hexagon);
    EXPECT_EQ(ui::settingLabel(slabs), "ewa, image-aligned slabs 0.5, post-classified");
    slabs.postClassified = false;
    EXPECT_EQ(ui::settingLabel(slabs), "ewa, image-aligned slabs 0.5");
}

TEST(Cli, ReportWritesAPageWhoseChartShowsTheMeasuredFigures) {
    const std::filesystem::path dir = testing_support::testOutputDir() / "cli_report";
    std::filesystem::remove_all(dir / "page");
    const CliRun r =
        splatlab("report \"" + testing_support::headsq() + "\" --out \"" + (dir / "page").string() +
                 "\" --cache \"" + (dir / "cache").string() + "\" --repeats 2 --size 24x20 --up -z");
    ASSERT_EQ(r.status, 0) << r.output;
    // The figures printed, a line per setting:
    // "headsq.nhdr | ewa, xray | 1.234 ms (p10 .., p90 ..) | 30.123 dB".
    std::vector<renderer::FilterMeasurement> printed;
    const std::regex line(
        R"(headsq\.nhdr \| [a-z-]+, [a-z-]+ \| ([0-9.]+) ms \(p10 ([0-9.]+), p90 ([0-9.]+)\) \| ([0-9.inf-]+) dB)");
    for (auto it = std::sregex_iterator(r.output.begin(), r.output.end(), line); it != std::sregex_iterator();
         ++it) {
        renderer::FilterMeasurement m;
        m.frameMs = std::stod((*it)[1]), m.p10Ms = std::stod((*it)[2]), m.p90Ms = std::stod((*it)[3]);
        m.psnrDb = std::stod((*it)[4]);
        printed.push_back(m);
    }
    ASSERT_EQ(printed.size(), 16u) << r.output;
    std::ifstream in(dir / "page" / "index.html");
    const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_THAT(html, HasSubstr("<h2>headsq.nhdr</h2>"));
    EXPECT_THAT(html, HasSubstr("threads")) << "the machine is named";
    EXPECT_THAT(r.output, HasSubstr("index.html: written in"));
    // The chart's points: figures as data- attributes, the marker where the axes put them.
    const std::regex point(
        R"re(<g class="point" data-setting="([a-z-]+), ([a-z-]+)" data-median-ms="([^"]+)" data-p10-ms="([^"]+)" data-p90-ms="([^"]+)" data-psnr-db="([^"]+)" data-pareto="([01])" data-current="([01])">.*?<line class="whisker" x1="([^"]+)" x2="([^"]+)".*?transform="translate\(([^,]+),([^)]+)\))re");
    std::vector<renderer::FilterMeasurement> charted;
    std::vector<bool> pareto, current;
    ui::SpeedErrorChart drawn;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), point); it != std::sregex_iterator();
         ++it) {
        const std::smatch& m = *it;
        renderer::FilterMeasurement f;
        f.filter = renderer::filterModeFromName(m[1]);
        f.compositing = renderer::compositingFromName(m[2]);
        f.frameMs = std::stod(m[3]), f.p10Ms = std::stod(m[4]), f.p90Ms = std::stod(m[5]),
        f.psnrDb = std::stod(m[6]);
        charted.push_back(f);
        pareto.push_back(m[7] == "1");
        current.push_back(m[8] == "1");
        drawn.points.push_back({std::stod(m[11]), std::stod(m[9]), std::stod(m[10]), std::stod(m[12]),
                                m[7] == "1", m[8] == "1"});
    }
    ASSERT_EQ(charted.size(), printed.size());
    for (size_t i = 0; i < charted.size(); ++i) {
        EXPECT_NEAR(charted[i].frameMs, printed[i].frameMs, 5e-4) << i;
        EXPECT_NEAR(charted[i].p10Ms, printed[i].p10Ms, 5e-4) << i;
        EXPECT_NEAR(charted[i].p90Ms, printed[i].p90Ms, 5e-4) << i;
        EXPECT_NEAR(charted[i].psnrDb, printed[i].psnrDb, 5e-4) << i;
    }
    // The markdown tables (speed.md) hold the same figures, in the same order, and the same front (to
    // their two decimals against the printed three: 5e-3 + 5e-4).
    std::ifstream mdIn(dir / "page" / "speed.md");
    const std::string md((std::istreambuf_iterator<char>(mdIn)), std::istreambuf_iterator<char>());
    EXPECT_THAT(md, HasSubstr("**headsq.nhdr**"));
    const std::regex row(R"(\| [a-z-]+, [a-z-]+ \| ([0-9.]+) \(([0-9.]+)-([0-9.]+)\) \| ([0-9.inf-]+) \| (yes)? \|)");
    size_t rows = 0;
    for (auto it = std::sregex_iterator(md.begin(), md.end(), row); it != std::sregex_iterator(); ++it, ++rows) {
        ASSERT_LT(rows, printed.size());
        EXPECT_NEAR(std::stod((*it)[1]), printed[rows].frameMs, 5.5e-3) << rows;
        EXPECT_NEAR(std::stod((*it)[2]), printed[rows].p10Ms, 5.5e-3) << rows;
        EXPECT_NEAR(std::stod((*it)[3]), printed[rows].p90Ms, 5.5e-3) << rows;
        EXPECT_NEAR(std::stod((*it)[4]), printed[rows].psnrDb, 5.5e-3) << rows;
        EXPECT_EQ((*it)[5].matched, bool(pareto[rows])) << rows;
    }
    EXPECT_EQ(rows, printed.size()) << md;
    // The README's summary (summary.md): headsq's row holds each filter's printed figures in the compositing
    // in force (the defaults': sheets front to back), to the summary's two decimals.
    std::ifstream summaryIn(dir / "page" / "summary.md");
    const std::string summary((std::istreambuf_iterator<char>(summaryIn)), std::istreambuf_iterator<char>());
    std::smatch cells;
    ASSERT_TRUE(std::regex_search(
        summary, cells,
        std::regex(R"(\| headsq\.nhdr \| 64x64x93, TF headsq, 24x20 px \|(( [0-9.]+ ms, [0-9.inf-]+ dB \|){4}) ([^|]*) \|)")))
        << summary;
    const std::string filterCells = cells[1];
    const std::regex cell(R"(([0-9.]+) ms, ([0-9.inf-]+) dB)");
    size_t filterIndex = 0;
    for (auto it = std::sregex_iterator(filterCells.begin(), filterCells.end(), cell); it != std::sregex_iterator();
         ++it, ++filterIndex) {
        const renderer::FilterMode filter = std::array{renderer::FilterMode::Ewa, renderer::FilterMode::Adaptive,
                                                       renderer::FilterMode::Reconstruction,
                                                       renderer::FilterMode::LowPass}[filterIndex];
        const auto at = std::find_if(charted.begin(), charted.end(), [&](const renderer::FilterMeasurement& m) {
            return m.filter == filter && m.compositing == renderer::Compositing::SheetFrontToBack;
        });
        ASSERT_NE(at, charted.end());
        EXPECT_NEAR(std::stod((*it)[1]), at->frameMs, 5.5e-3) << filterIndex;
        EXPECT_NEAR(std::stod((*it)[2]), at->psnrDb, 5.5e-3) << filterIndex;
    }
    EXPECT_EQ(filterIndex, 4u);
    size_t onFront = 0;
    for (bool p : pareto) onFront += p;
    EXPECT_EQ(size_t(std::count(cells[3].first, cells[3].second, ';')) + 1, onFront) << "the front's settings listed";
    // The axes of the SVG, and the points placed on them as the figures say.
    const std::regex axes(
        R"re(data-left="([^"]+)" data-right="([^"]+)" data-top="([^"]+)" data-bottom="([^"]+)" data-ms-lo="([^"]+)" data-ms-hi="([^"]+)" data-db-lo="([^"]+)" data-db-hi="([^"]+)")re");
    std::smatch a;
    ASSERT_TRUE(std::regex_search(html, a, axes));
    drawn.left = std::stod(a[1]), drawn.right = std::stod(a[2]), drawn.top = std::stod(a[3]);
    drawn.bottom = std::stod(a[4]);
    drawn.timeMs = {std::stod(a[5]), std::stod(a[6]), {}};
    drawn.psnrDb = {std::stod(a[7]), std::stod(a[8]), {}};
    renderer::SplatSettings defaults; // the report's settings in force: the defaults
    expectChartShows(drawn, charted, defaults, 0.01);
    // Thumbnails beside the page.
    for (const char* file : {"scan1_view.png", "scan1_truth.png", "scan1_ewa_xray.png",
                             "scan1_adaptive_sheet-front-to-back.png"})
        EXPECT_TRUE(std::filesystem::exists(dir / "page" / file)) << file;
}

TEST(Cli, ReportTimesImageAlignedSlabsLastAgainstTheirOwnTruth) {
    // --image-slabs 1 --post-classify: a 17th row, the slabs, compared with the post-classified truth, with
    // its crop thumbnail and its point on the chart; the summary's sheets cells stay the sheets'.
    const std::filesystem::path dir = testing_support::testOutputDir() / "cli_report_slabs";
    std::filesystem::remove_all(dir / "page");
    const CliRun r = splatlab("report \"" + testing_support::headsq() + "\" --out \"" + (dir / "page").string() +
                              "\" --cache \"" + (dir / "cache").string() +
                              "\" --repeats 1 --size 24x20 --up -z --image-slabs 1 --post-classify");
    ASSERT_EQ(r.status, 0) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        r.output, m,
        std::regex(R"(headsq\.nhdr \| ewa, image-aligned slabs 1, post-classified \| [0-9.]+ ms .* \| ([0-9.inf-]+) dB)")))
        << r.output;
    // Measured 20.4 dB (the sheets 24.3): headsq at 24x20 px is minified about 3 voxels a pixel, where one
    // post-classified sample a pixel aliases against the truth's 1-px filter (accuracy.md's 2x2 column).
    EXPECT_GT(std::stod(m[1]), 17.0) << "post-classified slabs against the post-classified truth";
    EXPECT_TRUE(std::filesystem::exists(dir / "page" / "scan1_ewa_slabs-1-post.png"));
    std::ifstream in(dir / "page" / "index.html");
    const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_THAT(html, HasSubstr("data-setting=\"ewa, image-aligned slabs 1, post-classified\""));
    const CliRun alone = splatlab("report \"" + testing_support::headsq() + "\" --out \"" +
                                  (dir / "page2").string() + "\" --post-classify");
    EXPECT_NE(alone.status, 0);
    EXPECT_THAT(alone.output, HasSubstr("--post-classify: applies to image-aligned slabs"));
}

TEST(Cli, ReportRefusesABadVolumeOrFolderWithOneClearLine) {
    const std::filesystem::path dir = testing_support::testOutputDir("cli_report_bad");
    const std::string file = (dir / "a_file.txt").string();
    std::ofstream(file) << "not a folder";
    const std::pair<std::string, std::string> cases[] = {
        {"report no_such_scan.nhdr --out \"" + (dir / "x").string() + "\"",
         "no_such_scan.nhdr: no such file (a volume file was expected)"},
        {"report \"" + testing_support::headsq() + "\" --out \"" + file + "/sub\"",
         "cannot create the report folder"},
        {"report \"" + testing_support::headsq() + "\" --out \"" + (dir / "x").string() + "\" --repeats 0",
         "--repeats"},
        {"report \"" + testing_support::headsq() + "\" --out \"" + (dir / "x").string() + "\" --size 40",
         "expected WxH"},
        {"report \"" + testing_support::headsq() + "\" --out \"" + (dir / "x").string() + "\" --up y,z",
         "one axis for every volume or one per volume (1), not 2"},
        {"report \"" + testing_support::headsq() + "\" --out \"" + (dir / "x").string() + "\" --up w",
         "up axis 'w': expected x, y, z, -x, -y or -z"},
    };
    for (const auto& [args, message] : cases) {
        const CliRun r = splatlab(args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_THAT(r.output, HasSubstr(message)) << args;
        EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 2)
            << r.output; // one line (CLI11 may add a hint)
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "x" / "index.html"));
}
