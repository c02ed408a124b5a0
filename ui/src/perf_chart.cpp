// The Performance chart: its window on the recorded renders (zoom, pan) and its drawing.
#include "ui/perf_chart.h"

#include "widgets.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace ui {

namespace {

double clampedShown(const PerfSettings& perf) {
    return std::clamp(perf.shown, kMinChartColumns, double(PerfHistory::kCapacity));
}

// The whole columns a window of perf.shown holds, and the farthest it may pan from the newest.
size_t wholeColumns(const PerfSettings& perf) {
    return std::max<size_t>(1, size_t(std::floor(clampedShown(perf))));
}
double maxOffset(const PerfSettings& perf, size_t samples) {
    return samples > wholeColumns(perf) ? double(samples - wholeColumns(perf)) : 0.0;
}

void clampOffset(PerfSettings& perf, size_t samples) {
    perf.newestOffset = std::clamp(perf.newestOffset, 0.0, maxOffset(perf, samples));
}

} // namespace

std::string renderBreakdownText(const PerfSample& s) {
    std::string text = "render " + std::to_string(s.frame);
    char line[128];
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
        std::snprintf(line, sizeof line, "\nfirst use of %d shader programs: includes compiling them",
                      s.firstUsePrograms);
        text += line;
    }
    return text;
}

ChartWindow chartWindow(const PerfSettings& perf, size_t samples) {
    if (samples == 0) return {};
    const size_t offset = size_t(std::clamp(perf.newestOffset, 0.0, maxOffset(perf, samples)));
    const size_t last = samples - offset; // one past the newest shown
    const size_t first = last > wholeColumns(perf) ? last - wholeColumns(perf) : 0;
    return {first, last - first};
}

void zoomChart(PerfSettings& perf, size_t samples, double notches, double anchor) {
    const double before = clampedShown(perf);
    const double after =
        std::clamp(before * std::pow(0.8, notches), kMinChartColumns, double(PerfHistory::kCapacity));
    // The render under the anchor is (1 - anchor) x shown columns from the right edge: keep it there.
    perf.newestOffset += (1.0 - std::clamp(anchor, 0.0, 1.0)) * (before - after);
    perf.shown = after;
    clampOffset(perf, samples);
}

void panChart(PerfSettings& perf, size_t samples, double columns) {
    perf.newestOffset += columns;
    clampOffset(perf, samples);
}

void resetChart(PerfSettings& perf) {
    perf.shown = double(PerfHistory::kCapacity);
    perf.newestOffset = 0.0;
}

void drawPerfChart(PerfSettings& perf, const PerfHistory& history, float height) {
    const auto& samples = history.samples();
    const ImGuiIO& io = ImGui::GetIO();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = std::max(ImGui::GetContentRegionAvail().x, 32.0f);
    ImGui::InvisibleButton("##perf_chart", ImVec2(width, height));
    const bool hovered = ImGui::IsItemHovered();
    // 1. Input: a drag pans (right: older renders), the wheel zooms about the pointer, a double-click shows
    // all.
    if (ImGui::IsItemActive() && io.MouseDelta.x != 0.0f)
        panChart(perf, samples.size(), double(io.MouseDelta.x) * clampedShown(perf) / double(width));
    if (hovered && io.MouseWheel != 0.0f)
        zoomChart(perf, samples.size(), io.MouseWheel, double((io.MousePos.x - origin.x) / width));
    if (hovered && ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) resetChart(perf);
    clampOffset(perf, samples.size()); // the history may have been cleared
    perf.hoveredFrame.reset();

    // 2. The frame, or a note while there is nothing to show.
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
    const ChartWindow shown = chartWindow(perf, samples.size());
    const float cw = width / float(clampedShown(perf));
    // 3. The scale fits every render shown but outliers (a first render compiling its shaders): at most
    //    twice the history's p95; taller columns are cut at the top.
    double top = 1.0;
    for (size_t i = shown.first; i < shown.first + shown.count; ++i)
        top = std::max({top, samples[i].gpuMs, samples[i].cpuMs});
    top = std::min(top, 2.0 * std::max(history.summary().gpuP95Ms, 0.5)) * 1.15;
    const auto yOf = [&](double ms) { return std::max(end.y - float(ms / top) * height, origin.y); };
    // 4. The columns: the newest shown at the right edge, filling in leftwards.
    const float x0 = end.x - cw * float(shown.count);
    const size_t hoveredColumn = hovered && io.MousePos.x >= x0
                                     ? std::min(size_t((io.MousePos.x - x0) / cw), shown.count - 1)
                                     : shown.count;
    draw->PushClipRect(origin, end, true);
    for (size_t i = 0; i < shown.count; ++i) {
        const PerfSample& s = samples[shown.first + i];
        const float xa = x0 + cw * float(i), xb = xa + std::max(cw - 1.0f, 1.0f);
        if (i == hoveredColumn)
            draw->AddRectFilled(ImVec2(xa, origin.y), ImVec2(xb, end.y), IM_COL32(255, 255, 255, 40));
        double below = 0.0;
        for (int p = 0; p < renderer::kGpuPasses; ++p) {
            const double ms = s.passMs[size_t(p)];
            if (!(ms > 0.0)) continue;
            draw->AddRectFilled(ImVec2(xa, yOf(below + ms)), ImVec2(xb, yOf(below)),
                                passColour(p, renderer::kGpuPasses));
            below += ms;
        }
        draw->AddLine(ImVec2(xa, yOf(s.cpuMs)), ImVec2(xb + 1.0f, yOf(s.cpuMs)), IM_COL32(255, 255, 255, 220),
                      2.0f);
    }
    draw->PopClipRect();
    // 5. Rate lines, the scale, and which renders are shown.
    float lastLabelY = end.y;
    for (auto [ms, label] : {std::pair{1000.0 / 60.0, "60 /s"}, std::pair{1000.0 / 30.0, "30 /s"}}) {
        const float y = yOf(ms);
        if (ms >= top || lastLabelY - y < ImGui::GetFontSize()) continue; // off the scale, or crowded
        lastLabelY = y;
        for (float x = origin.x; x < end.x; x += 8.0f)
            draw->AddLine(ImVec2(x, y), ImVec2(std::min(x + 4.0f, end.x), y), IM_COL32(255, 255, 255, 90));
        draw->AddText(ImVec2(origin.x + 4.0f, y - ImGui::GetFontSize()), IM_COL32(255, 255, 255, 140), label);
    }
    char text[96];
    std::snprintf(text, sizeof text, "%.1f ms", top);
    const ImU32 grey = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    draw->AddText(ImVec2(end.x - ImGui::CalcTextSize(text).x - 4.0f, origin.y + 2.0f), grey, text);
    std::snprintf(text, sizeof text, "renders %llu..%llu (%zu of %zu)%s",
                  (unsigned long long)samples[shown.first].frame,
                  (unsigned long long)samples[shown.first + shown.count - 1].frame, shown.count,
                  samples.size(), history.paused() ? ", paused" : "");
    draw->AddText(ImVec2(origin.x + 4.0f, origin.y + 2.0f), grey, text);
    if (hoveredColumn < shown.count) {
        const PerfSample& s = samples[shown.first + hoveredColumn];
        perf.hoveredFrame = s.frame;
        ImGui::SetTooltip("%s", renderBreakdownText(s).c_str());
    }
}

} // namespace ui
