// The Performance panel: the load (continuous rendering, spin), the summary of recent renders and a
// chart of each render's GPU time split by pass, its CPU time drawn over it.
#include "ui/panels.h"

#include "widgets.h"

#include <algorithm>
#include <cstdio>

namespace ui {

namespace {

// One column per render, oldest on the left: its passes stacked from the bottom (the GPU time), a white
// tick at its CPU time, and dashed lines at 60 and 30 renders a second when they are in range. Hover a
// column for its figures.
void drawChart(const PerfHistory& history, float height) {
    const auto& samples = history.samples();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = std::max(ImGui::GetContentRegionAvail().x, 32.0f);
    ImGui::InvisibleButton("##perf_chart", ImVec2(width, height));
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 end(origin.x + width, origin.y + height);
    draw->AddRectFilled(origin, end, ImGui::GetColorU32(ImGuiCol_FrameBg));
    if (samples.empty()) {
        const char* note = "no timed renders yet: edit the view, or render continuously";
        const ImVec2 size = ImGui::CalcTextSize(note);
        draw->AddText(ImVec2(origin.x + (width - size.x) * 0.5f, origin.y + (height - size.y) * 0.5f),
                      ImGui::GetColorU32(ImGuiCol_TextDisabled), note);
        return;
    }
    // The scale fits every render but outliers (a first render compiling its shaders): at most twice
    // the p95; taller columns are cut at the top.
    double top = 1.0;
    for (const PerfSample& s : samples) top = std::max({top, s.gpuMs, s.cpuMs});
    top = std::min(top, 2.0 * std::max(history.summary().gpuP95Ms, 0.5)) * 1.15;
    const auto yOf = [&](double ms) { return std::max(end.y - float(ms / top) * height, origin.y); };
    const float column = width / float(PerfHistory::kCapacity);
    // The newest render sits at the right edge; the history fills in leftwards.
    const float x0 = end.x - column * float(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
        const PerfSample& s = samples[i];
        const float xa = x0 + column * float(i), xb = xa + std::max(column - 1.0f, 1.0f);
        double below = 0.0;
        for (int p = 0; p < renderer::kGpuPasses; ++p) {
            const double ms = s.passMs[size_t(p)];
            if (!(ms > 0.0)) continue;
            draw->AddRectFilled(ImVec2(xa, yOf(below + ms)), ImVec2(xb, yOf(below)),
                                passColour(p, renderer::kGpuPasses));
            below += ms;
        }
        draw->AddLine(ImVec2(xa, yOf(s.cpuMs)), ImVec2(xb + 1.0f, yOf(s.cpuMs)), IM_COL32(255, 255, 255, 220), 2.0f);
    }
    float lastLabelY = end.y;
    for (auto [ms, label] : {std::pair{1000.0 / 60.0, "60 /s"}, std::pair{1000.0 / 30.0, "30 /s"}}) {
        const float y = yOf(ms);
        if (ms >= top || lastLabelY - y < ImGui::GetFontSize()) continue;   // off the scale, or crowded
        lastLabelY = y;
        for (float x = origin.x; x < end.x; x += 8.0f)
            draw->AddLine(ImVec2(x, y), ImVec2(std::min(x + 4.0f, end.x), y), IM_COL32(255, 255, 255, 90));
        draw->AddText(ImVec2(origin.x + 4.0f, y - ImGui::GetFontSize()), IM_COL32(255, 255, 255, 140), label);
    }
    char scale[32];
    std::snprintf(scale, sizeof scale, "%.1f ms", top);
    draw->AddText(ImVec2(end.x - ImGui::CalcTextSize(scale).x - 4.0f, origin.y + 2.0f),
                  ImGui::GetColorU32(ImGuiCol_TextDisabled), scale);
    if (!ImGui::IsItemHovered()) return;
    const float mx = ImGui::GetIO().MousePos.x;
    if (mx < x0) return;
    const PerfSample& s = samples[std::min(size_t((mx - x0) / column), samples.size() - 1)];
    std::string text = "render " + std::to_string(s.frame);
    char line[96];
    std::snprintf(line, sizeof line, "\ngpu %.2f ms   cpu %.2f ms", s.gpuMs, s.cpuMs);
    text += line;
    if (s.intervalMs > 0.0) {
        std::snprintf(line, sizeof line, "\n%.1f ms after the last render", s.intervalMs);
        text += line;
    }
    if (const std::string passes = passListText(s.passMs, "\n  "); !passes.empty()) text += "\n  " + passes;
    std::snprintf(line, sizeof line, "\n%llu splats, %.1f KiB uploaded", (unsigned long long)s.splats,
                  double(s.uploadBytes) / 1024.0);
    text += line;
    if (s.firstUsePrograms > 0) {
        std::snprintf(line, sizeof line, "\nfirst use of %d shader programs: includes compiling them", s.firstUsePrograms);
        text += line;
    }
    ImGui::SetTooltip("%s", text.c_str());
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
    if (ImGui::SliderFloat("Spin (deg/s)", &spin, -90.0f, 90.0f, "%.0f")) perf.spinDegPerS = double(spin);
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

    // Chart column.
    ImGui::TableNextColumn();
    drawChart(history, std::max(ImGui::GetContentRegionAvail().y - ImGui::GetStyle().WindowPadding.y,
                                ImGui::GetFontSize() * 6.0f));
    ImGui::EndTable();
}

} // namespace ui
