// The Performance chart you can inspect: Pause freezes the recorded renders while renders go on, the
// wheel and a drag zoom and pan over them, hovering a render gives its pass breakdown, and Export CSV
// writes rows equal to the recorded values; the bottom strip shows Measure's table and the chart at 1280x800.
#include "editor_window.h"
#include "imgui_null.h"
#include "test_paths.h"
#include "ui/dock_layout.h"
#include "ui/panels.h"
#include "ui/perf_chart.h"
#include "ui/perf_csv.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <charconv>
#include <fstream>
#include <sstream>

using ::testing::HasSubstr;

namespace {

// Render k: CPU k/3 ms, GPU 2k + 0.1 ms split over two passes, k x 1000 splats (fractions that need
// every digit to read back exactly).
void record(ui::PerfHistory& h, uint64_t k) {
    renderer::FrameStats f;
    f.frame = k;
    f.cpuMs = double(k) / 3.0;
    f.splatsDrawn = 1000 * k;
    f.frameUploadBytes = 7 * k;
    f.firstUsePrograms = k == 1 ? 6 : 0;
    h.addRender(f, k > 1 ? 16.0 + 1.0 / double(k) : 0.0);
    renderer::FrameStats t;
    t.gpuFrame = k;
    t.gpuMs = 2.0 * double(k) + 0.1;
    t.passMs[size_t(renderer::GpuPass::Splats)] = 0.7 * t.gpuMs;
    t.passMs[size_t(renderer::GpuPass::Composite)] = 0.3 * t.gpuMs;
    h.addTimes(t);
}

std::vector<std::string> split(const std::string& text, char by) {
    std::vector<std::string> parts;
    std::stringstream stream(text);
    for (std::string part; std::getline(stream, part, by);)
        parts.push_back(part);
    return parts;
}

double number(const std::string& text) {
    double v = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
    EXPECT_TRUE(error == std::errc() && end == text.data() + text.size())
        << "'" << text << "' is not a number";
    return v;
}

} // namespace

class PerformanceChart : public ImGuiNull {
  protected:
    ui::EditorState state;
    ui::PerfHistory history;
    void SetUp() override {
        ImGuiNull::SetUp();
        windowWidth = 955.0f, windowHeight = 260.0f; // the bottom strip of a 1280x800 window
    }
    void body() { ui::drawPerformancePanel(state, history); }
    // Clicks along the chart column's first row (under the fixture window's title bar) until `done`.
    template <class Done> void clickChartToolbar(Done done) {
        auto draw = [&] { body(); };
        for (float x = 310.0f; x < 940.0f && !done(); x += 6.0f)
            click(x, 38.0f, draw);
    }
};

TEST_F(PerformanceChart, PauseKeepsTheRecordedRendersWhileRendersGoOn) {
    for (uint64_t k = 1; k <= 30; ++k)
        record(history, k);
    frame([&] { body(); });
    clickChartToolbar([&] { return history.paused(); });
    ASSERT_TRUE(history.paused()) << "no Pause button over the chart";
    const std::deque<ui::PerfSample> before = history.samples();
    for (uint64_t k = 31; k <= 60; ++k) { // renders go on, a UI frame each
        record(history, k);
        frame([&] { body(); });
    }
    ASSERT_EQ(history.samples().size(), before.size());
    for (size_t i = 0; i < before.size(); ++i) {
        EXPECT_EQ(history.samples()[i].frame, before[i].frame);
        EXPECT_EQ(history.samples()[i].gpuMs, before[i].gpuMs);
    }
    // Resume (the same button): renders from then on are recorded again.
    clickChartToolbar([&] { return !history.paused(); });
    ASSERT_FALSE(history.paused());
    record(history, 61);
    EXPECT_EQ(history.samples().back().frame, 61u);
}

TEST(PerfChartWindow, ZoomKeepsTheRenderUnderThePointerAndPanStaysOnTheRecordedRenders) {
    ui::PerfSettings perf;
    EXPECT_EQ(ui::chartWindow(perf, 0).count, 0u);
    EXPECT_EQ(ui::chartWindow(perf, 100).first, 0u); // fewer renders than columns: all of them
    EXPECT_EQ(ui::chartWindow(perf, 100).count, 100u);
    // 240 renders, zoomed in 3 notches about the middle: 0.8^3 x 240 = 122.88 columns, centred where the
    // middle was (render 120 of 0..239).
    ui::zoomChart(perf, 240, 3.0, 0.5);
    EXPECT_DOUBLE_EQ(perf.shown, 240.0 * 0.512);
    const ui::ChartWindow w = ui::chartWindow(perf, 240);
    EXPECT_EQ(w.count, 122u);
    EXPECT_NEAR(double(w.first) + 0.5 * double(w.count), 120.0, 1.0);
    // Pans stop at the oldest and at the newest renders.
    ui::panChart(perf, 240, 1000.0);
    EXPECT_EQ(ui::chartWindow(perf, 240).first, 0u);
    ui::panChart(perf, 240, -1000.0);
    EXPECT_EQ(ui::chartWindow(perf, 240).first + ui::chartWindow(perf, 240).count, 240u);
    // Zooming stops at kMinChartColumns and at every render.
    ui::zoomChart(perf, 240, 100.0, 1.0);
    EXPECT_EQ(perf.shown, ui::kMinChartColumns);
    ui::zoomChart(perf, 240, -100.0, 1.0);
    EXPECT_EQ(perf.shown, double(ui::PerfHistory::kCapacity));
}

TEST_F(PerformanceChart, WheelZoomsDragPansDoubleClickShowsAllAndHoverGivesARendersPasses) {
    for (uint64_t k = 1; k <= ui::PerfHistory::kCapacity; ++k)
        record(history, k);
    frame([&] { body(); });
    // The chart fills the panel's right column below its toolbar: (800, 150) is on it.
    mouse(800.0f, 150.0f, false);
    ImGui::GetIO().MouseWheel = 2.0f;
    frame([&] { body(); });
    ImGui::GetIO().MouseWheel = 0.0f;
    EXPECT_LT(state.perf.shown, 240.0) << "the wheel did not zoom";
    const ui::ChartWindow zoomed = ui::chartWindow(state.perf, history.samples().size());
    EXPECT_LT(zoomed.count, 240u);
    EXPECT_GT(zoomed.first, 0u);
    // A drag to the right shows older renders.
    mouse(800.0f, 150.0f, true);
    frame([&] { body(); });
    mouse(900.0f, 150.0f, true);
    frame([&] { body(); });
    mouse(900.0f, 150.0f, false);
    frame([&] { body(); });
    EXPECT_LT(ui::chartWindow(state.perf, history.samples().size()).first, zoomed.first)
        << "the drag did not pan";
    EXPECT_GT(state.perf.newestOffset, 0.0);
    // Hovering a column opens a tooltip of its render's times and passes; the column under the pointer
    // is a render of the window shown, and moving the pointer along the chart changes it.
    mouse(900.0f, 150.0f, false);
    frame([&] { body(); });
    const ui::ChartWindow panned = ui::chartWindow(state.perf, history.samples().size());
    ASSERT_TRUE(state.perf.hoveredFrame);
    const uint64_t hovered = *state.perf.hoveredFrame;
    EXPECT_GE(hovered, history.samples()[panned.first].frame);
    EXPECT_LE(hovered, history.samples()[panned.first + panned.count - 1].frame);
    const ImGuiWindow* tooltip = ImGui::FindWindowByName("##Tooltip_00");
    EXPECT_TRUE(tooltip && tooltip->Active) << "no tooltip";
    mouse(700.0f, 150.0f, false);
    frame([&] { body(); });
    ASSERT_TRUE(state.perf.hoveredFrame);
    EXPECT_LT(*state.perf.hoveredFrame, hovered);
    const ui::PerfSample& sample = history.samples()[size_t(hovered - history.samples().front().frame)];
    const std::string text = ui::renderBreakdownText(sample);
    EXPECT_THAT(text, HasSubstr("render " + std::to_string(hovered)));
    EXPECT_THAT(text, HasSubstr(ui::passListText(sample.passMs, "\n  "))); // splats and composite, in ms
    EXPECT_THAT(text, HasSubstr(std::to_string(sample.splats) + " splats"));
    // A double-click shows every render again.
    click(800.0f, 150.0f, [&] { body(); });
    click(800.0f, 150.0f, [&] { body(); });
    EXPECT_EQ(state.perf.shown, 240.0);
    EXPECT_EQ(state.perf.newestOffset, 0.0);
}

TEST(PerfCsv, RowsEqualTheRecordedValues) {
    ui::PerfHistory history;
    for (uint64_t k = 1; k <= 25; ++k)
        record(history, k);
    const std::vector<std::string> lines = split(ui::perfCsv(history.samples()), '\n');
    ASSERT_EQ(lines.size(), history.samples().size() + 1);
    const std::vector<std::string> header = split(lines[0], ',');
    ASSERT_EQ(header.size(), 4u + renderer::kGpuPasses + 3u);
    EXPECT_EQ(header[0], "frame");
    EXPECT_EQ(header[3], "gpu_ms");
    EXPECT_EQ(header[4], "select_buckets_ms");
    EXPECT_EQ(header.back(), "first_use_programs");
    for (size_t i = 0; i < history.samples().size(); ++i) {
        const ui::PerfSample& s = history.samples()[i];
        const std::vector<std::string> row = split(lines[i + 1], ',');
        ASSERT_EQ(row.size(), header.size());
        EXPECT_EQ(number(row[0]), double(s.frame));
        EXPECT_EQ(number(row[1]), s.intervalMs); // exactly: the shortest text that reads back the same
        EXPECT_EQ(number(row[2]), s.cpuMs);
        EXPECT_EQ(number(row[3]), s.gpuMs);
        for (int p = 0; p < renderer::kGpuPasses; ++p)
            EXPECT_EQ(number(row[4 + size_t(p)]), s.passMs[size_t(p)]);
        EXPECT_EQ(number(row[4 + renderer::kGpuPasses]), double(s.splats));
        EXPECT_EQ(number(row[5 + renderer::kGpuPasses]), double(s.uploadBytes));
        EXPECT_EQ(number(row[6 + renderer::kGpuPasses]), double(s.firstUsePrograms));
    }
}

TEST_F(PerformanceChart, ExportCsvWritesTheRecordedRendersAtomicallyToThePathField) {
    for (uint64_t k = 1; k <= 12; ++k)
        record(history, k);
    const std::filesystem::path dir = testing_support::testOutputDir("perf_csv");
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    state.perf.csvFile = (dir / "frames.csv").string();
    std::ofstream(dir / "frames.csv") << "an older export\n";
    frame([&] { body(); });
    clickChartToolbar([&] { return !state.perf.csvSaved.empty(); });
    ASSERT_EQ(state.perf.csvSaved, "wrote 12 renders to frames.csv") << "no Export CSV button over the chart";
    std::ifstream in(dir / "frames.csv");
    const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(written, ui::perfCsv(history.samples()));
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1) << "a temporary file was left";
    // A path it cannot write: the error dialog names it, and nothing else changes.
    state.perf.csvFile = (dir / "missing" / "frames.csv").string();
    state.perf.csvSaved.clear();
    clickChartToolbar([&] { return !state.errorMessage.empty(); });
    EXPECT_THAT(state.errorMessage, HasSubstr("frames.csv"));
    EXPECT_TRUE(state.perf.csvSaved.empty());
}

// At 1280x800 the default layout's bottom strip shows the Filters panel with four filters measured, and
// the Performance chart, without scrolling or resizing.
TEST_F(ImGuiNull, BottomStripShowsMeasuresTableAndTheChartAt1280x800) {
    const ui::DockLayout layout = ui::makeEditorLayout();
    const ui::Rect bottom = ui::computeDockRects(layout, testing_support::kEditorDockArea)
                                .node[size_t(layout.find("bottom"))]; // under the menu bar
    windowWidth = bottom.w, windowHeight = bottom.h;
    ui::EditorState state;
    const renderer::ImagePlane plane =
        renderer::makeImagePlane(renderer::Camera{}, {32, 32, 46}, 60.0, 955, 545);
    ui::FiltersView view;
    view.plane = &plane;
    view.dims = {64, 64, 93};
    view.radius = 60.0;
    view.cropPx = 96;
    view.patches = std::array<uint64_t, 3>{10, 0, 30};
    view.frame.hasCounters = true;
    view.measurements = {{.filter = renderer::FilterMode::Reconstruction, .frameMs = 184.0, .rmse = 0.0042, .psnrDb = 47.6},
                         {.filter = renderer::FilterMode::LowPass, .frameMs = 28.7, .rmse = 0.143, .psnrDb = 16.9},
                         {.filter = renderer::FilterMode::Ewa, .frameMs = 175.0, .rmse = 0.0046, .psnrDb = 46.8},
                         {.filter = renderer::FilterMode::Adaptive, .frameMs = 175.0, .rmse = 0.0045, .psnrDb = 46.9}};
    view.measurementsStale = true;
    float scroll = -1.0f;
    // Inside a tab bar, as the editor docks it.
    auto inTab = [&](const std::function<void()>& panel) {
        return [&, panel] {
            if (ImGui::BeginTabBar("##tabs")) {
                if (ImGui::BeginTabItem("Panel")) {
                    panel();
                    ImGui::EndTabItem();
                }
                ImGui::EndTabBar();
            }
            scroll = ImGui::GetScrollMaxY();
        };
    };
    const auto filters = inTab([&] { ui::drawFiltersPanel(state, view); });
    for (int i = 0; i < 3; ++i)
        frame(filters); // the content's size is known from the second frame
    EXPECT_EQ(scroll, 0.0f) << "the Filters panel needs " << scroll << " px more than the bottom strip's "
                            << bottom.h;
    ui::PerfHistory history;
    for (uint64_t k = 1; k <= 60; ++k)
        record(history, k);
    const auto performance = inTab([&] { ui::drawPerformancePanel(state, history); });
    for (int i = 0; i < 3; ++i)
        frame(performance);
    EXPECT_EQ(scroll, 0.0f) << "the Performance panel needs " << scroll << " px more";
}
