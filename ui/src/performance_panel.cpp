// The Performance panel: the load (continuous rendering, spin), the summary of recent renders, pause,
// CSV export, and the chart of each render's GPU time split by pass (perf_chart.h).
#include "ui/panels.h"

#include "renderer/errors.h"
#include "ui/perf_chart.h"
#include "ui/perf_csv.h"
#include "widgets.h"

#include <algorithm>
#include <cstdio>

namespace ui {

namespace {

// Over the chart: Pause, the path field and Export CSV (the recorded renders, a row each, perf_csv.h,
// written atomically), and what the last export wrote.
void drawChartControls(EditorState& state, PerfHistory& history) {
    PerfSettings& perf = state.perf;
    if (ImGui::Button(history.paused() ? "Resume" : "Pause")) history.setPaused(!history.paused());
    hint("Freeze the recorded renders to inspect them; rendering goes on, and renders while paused are not\n"
         "recorded. On the chart: the wheel zooms, a drag pans, a double-click shows all, hover a render\n"
         "for its passes");
    ImGui::SameLine();
    // The path takes what is left of the row beside Export CSV, up to 16 characters' room.
    const ImGuiStyle& style = ImGui::GetStyle();
    const float button = ImGui::CalcTextSize("Export CSV").x + 2.0f * style.FramePadding.x + style.ItemSpacing.x;
    ImGui::SetNextItemWidth(std::clamp(ImGui::GetContentRegionAvail().x - button, ImGui::GetFontSize() * 4.0f,
                                       ImGui::GetFontSize() * 16.0f));
    inputPath("##csv", perf.csvFile);
    hint("Where Export CSV writes the recorded renders");
    ImGui::SameLine();
    ImGui::BeginDisabled(history.samples().empty());
    if (ImGui::Button("Export CSV")) {
        try {
            writePerfCsv(perf.csvFile, history.samples());
            perf.csvSaved = "wrote " + std::to_string(history.samples().size()) + " renders to " +
                            std::filesystem::path(perf.csvFile).filename().string();
            state.saveNotice =
                savedNotice(perf.csvFile, std::to_string(history.samples().size()) + " renders");
        } catch (const renderer::LoadError& e) {
            state.errorMessage = e.what();
        }
    }
    ImGui::EndDisabled();
    hint("A row per recorded render: frame, interval, CPU, GPU and each pass in ms, splats, bytes uploaded");
    if (!perf.csvSaved.empty()) {
        sameLineIfFits(perf.csvSaved.c_str());
        ImGui::TextDisabled("%s", perf.csvSaved.c_str());
    }
}

} // namespace

void drawPerformancePanel(EditorState& state, PerfHistory& history, const std::function<std::string()>& context) {
    if (!ImGui::BeginTable("##performance", 2, ImGuiTableFlags_BordersInnerV)) return;
    // The summary takes what its lines need; the chart the rest.
    ImGui::TableSetupColumn("summary", ImGuiTableColumnFlags_WidthFixed, ImGui::GetFontSize() * 23.0f);
    ImGui::TableSetupColumn("chart", ImGuiTableColumnFlags_WidthStretch);
    ImGui::TableNextRow();

    // Summary column: the load, then the figures.
    ImGui::TableNextColumn();
    PerfSettings& perf = state.perf;
    ImGui::Checkbox("Render continuously", &perf.renderContinuously);
    hint("Re-render every UI frame, so the figures show a steady load\n"
         "(otherwise the editor renders only when the view changes)");
    ImGui::SameLine();
    if (ImGui::Button("Clear")) history.clear();
    hint("Forget the renders so far");
    ImGui::SameLine();
    ImGui::BeginDisabled(history.samples().empty());
    if (ImGui::Button("Copy")) ImGui::SetClipboardText(summaryText(history.summary(), context()).c_str());
    ImGui::EndDisabled();
    hint("The figures below as text, with the volume, image size, mode and GL_RENDERER, for a report");
    ImGui::BeginDisabled(!perf.renderContinuously);
    float spin = float(perf.spinDegPerS);
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 10.0f);
    if (numberField("Spin (deg/s)", spin,
                    [&] { return ImGui::SliderFloat("Spin (deg/s)", &spin, -90.0f, 90.0f, "%.0f"); }))
        perf.spinDegPerS = double(spin);
    numberHint("Turn the camera about the vertical while rendering continuously:\n"
         "every render is a new view (a turn past a diagonal uploads that axis's lists)");
    ImGui::EndDisabled();

    const PerfSummary sum = history.summary();
    if (sum.renders == 0) {
        ImGui::TextDisabled("no timed renders yet");
    } else {
        ImGui::Text("GPU %.2f ms (%.1f /s), median of %zu", sum.gpuMedianMs, 1000.0 / sum.gpuMedianMs, sum.renders);
        hint("GPU times arrive a few renders late (the timer ring never waits)");
        ImGui::TextDisabled("    p95 %.2f  min %.2f  max %.2f ms", sum.gpuP95Ms, sum.gpuMinMs, sum.gpuMaxMs);
        ImGui::Text("CPU %.2f ms", sum.cpuMedianMs);
        ImGui::SameLine();
        if (sum.intervals > 0)
            ImGui::Text("  renders %.1f /s", 1000.0 / sum.intervalMedianMs);
        else
            ImGui::TextDisabled("  renders -- /s");
        hint("Renders a second as the user sees them: the median time from one render's start to the\n"
             "next's, over renders that followed each other (render continuously)");
        ImGui::Text("splats sent %.3g /s", sum.splatsPerSecond);
        hint("The median render's splats over the median GPU time. Splats sent: every voxel of the\n"
             "buckets the transfer function shows, a few more than the visible voxels (Stats), since\n"
             "a bucket's voxels below the TF's first opacity are dropped by the vertex stage");
        drawPassList("passes", sum.passMedianMs);
    }

    // Chart column: its controls over it.
    ImGui::TableNextColumn();
    drawChartControls(state, history);
    drawPerfChart(perf, history, std::max(ImGui::GetContentRegionAvail().y - ImGui::GetStyle().WindowPadding.y,
                                          ImGui::GetFontSize() * 6.0f));
    ImGui::EndTable();
}

} // namespace ui
