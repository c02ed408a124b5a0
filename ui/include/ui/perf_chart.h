// The Performance panel's chart of recorded renders: which of them it shows (zoom and pan, as plain
// arithmetic the tests check) and its drawing with ImGui's draw list (ImPlot is not a Debian package).
#pragma once
#include "ui/editor_state.h"
#include "ui/perf_history.h"

#include <cstddef>
#include <string>

namespace ui {

constexpr double kMinChartColumns = 8.0; // the deepest zoom: columns as wide as a ninth of the chart

// The samples the chart shows: [first, first + count), oldest first, the last of them at the right edge.
struct ChartWindow {
    size_t first = 0, count = 0;
};
ChartWindow chartWindow(const PerfSettings& perf, size_t samples);

// Zooms by `notches` (positive: in, 0.8 times the columns a notch) about the point `anchor` of the
// chart's width (0 left edge, 1 right edge): the render under it stays under it. Clamped to
// kMinChartColumns..PerfHistory::kCapacity columns and to the samples there are.
void zoomChart(PerfSettings& perf, size_t samples, double notches, double anchor);
// Pans by `columns` (positive: towards older renders, as a drag to the right shows), clamped so that
// the window stays on the recorded renders.
void panChart(PerfSettings& perf, size_t samples, double columns);
// Back to every render (a double-click on the chart).
void resetChart(PerfSettings& perf);

// A render's tooltip on the chart: its GPU and CPU times, the interval before it, its GPU time per pass
// (the passes the Stats panel lists), splats, bytes uploaded, and whether it compiled shader programs.
std::string renderBreakdownText(const PerfSample& sample);

// One column per render shown, oldest on the left: its passes stacked from the bottom (the GPU time), a
// white tick at its CPU time, dashed lines at 60 and 30 renders a second when in range. The wheel zooms
// and a drag pans (perf's window); a double-click shows all. Hover a column for its figures and pass
// breakdown (renderBreakdownText; perf.hoveredFrame says which render).
void drawPerfChart(PerfSettings& perf, const PerfHistory& history, float height);

} // namespace ui
