// The Filters panel: which filter each part of the view takes, how much of it, and why (the depths
// where a kernel's size on screen crosses the adaptive thresholds, beside the volume's own depths).
#include "filter_colours.h"
#include "renderer/math/classifier.h"
#include "renderer/oracle/ground_truth.h"
#include "ui/panels.h"
#include "ui/speed_error_chart.h"
#include "ui/number_field.h"
#include "widgets.h"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>

namespace ui {

namespace {

// Shares of the three filters as one bar, each in its colour.
void shareBar(const std::array<uint64_t, 3>& counts) {
    const double total = double(counts[0] + counts[1] + counts[2]);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = std::max(ImGui::GetContentRegionAvail().x, 1.0f), height = ImGui::GetFontSize() * 0.7f;
    ImGui::Dummy(ImVec2(width, height));
    if (!(total > 0.0)) return;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    float x = origin.x;
    for (int m = 0; m < 3; ++m) {
        const float w = float(double(counts[size_t(m)]) / total) * width;
        draw->AddRectFilled(ImVec2(x, origin.y), ImVec2(x + w, origin.y + height), ImGui::GetColorU32(kModeColour[m]));
        x += w;
    }
}

void shareText(const char* what, const std::array<uint64_t, 3>& counts) {
    const double total = double(counts[0] + counts[1] + counts[2]);
    ImGui::Text("%s", what);
    for (int m = 0; m < 3; ++m) {
        char part[48];
        std::snprintf(part, sizeof part, "%s %.0f %%", kModeName[m],
                      total > 0.0 ? 100.0 * double(counts[size_t(m)]) / total : 0.0);
        sameLineIfFits(part);
        ImGui::TextColored(kModeColour[m], "%s", part);
    }
    shareBar(counts);
}

// The depth axis (log scale: the thresholds lie far apart) from just before the nearest of the volume
// and the reconstruction depth to just past the farthest of the volume and the low-pass depth, each
// depth in the colour of the filter a kernel takes there, and the volume's depths bracketed above it.
void drawDepthBar(const renderer::FilterDepths& d, glm::dvec2 volume, double radius) {
    const double lo = std::max(std::min(volume.x, d.reconstructionNearer), volume.y * 1e-3) / 1.3;
    const double hi = std::max(volume.y, d.lowPassFarther) * 1.3;
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = std::max(ImGui::GetContentRegionAvail().x, 1.0f), font = ImGui::GetFontSize();
    ImGui::Dummy(ImVec2(width, font * 2.6f));
    if (!(lo > 0.0) || !(hi > lo)) return;
    const bool hovered = ImGui::IsItemHovered();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    auto xOf = [&](double depth) {
        const double t = (std::log(std::max(depth, lo)) - std::log(lo)) / (std::log(hi) - std::log(lo));
        return origin.x + float(std::clamp(t, 0.0, 1.0)) * width;
    };
    const float barTop = origin.y + font * 0.5f, barBottom = origin.y + font * 1.2f;
    const double edges[4] = {lo, d.reconstructionNearer, d.lowPassFarther, hi};
    const int order[3] = {0, 2, 1};   // nearest first: reconstruction, EWA, low-pass
    for (int i = 0; i < 3; ++i)
        draw->AddRectFilled(ImVec2(xOf(edges[i]), barTop), ImVec2(xOf(edges[i + 1]), barBottom),
                            ImGui::GetColorU32(kModeColour[order[i]]));
    const ImU32 white = IM_COL32(240, 240, 240, 255);
    const float x0 = xOf(volume.x), x1 = xOf(volume.y), y = origin.y + font * 0.15f;
    draw->AddLine(ImVec2(x0, y), ImVec2(x1, y), white, 2.0f);
    draw->AddLine(ImVec2(x0, y), ImVec2(x0, barBottom), white, 1.5f);
    draw->AddLine(ImVec2(x1, y), ImVec2(x1, barBottom), white, 1.5f);
    char text[64];
    const ImU32 grey = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    std::snprintf(text, sizeof text, "%.2f", lo / radius);
    draw->AddText(ImVec2(origin.x, barBottom + font * 0.1f), grey, text);
    float ends = ImGui::CalcTextSize(text).x;
    std::snprintf(text, sizeof text, "%.2f", hi / radius);
    draw->AddText(ImVec2(origin.x + width - ImGui::CalcTextSize(text).x, barBottom + font * 0.1f), grey, text);
    ends = 2.0f * std::max(ends, ImGui::CalcTextSize(text).x) + 2.0f * font;
    // The axis's name between the two end depths: the long one where it fits, else the short one.
    for (const char* label : {"depth from the eye, log scale", "log depth"})
        if (ImGui::CalcTextSize(label).x + ends <= width) {
            draw->AddText(ImVec2(origin.x + (width - ImGui::CalcTextSize(label).x) * 0.5f, barBottom + font * 0.1f),
                          grey, label);
            break;
        }
    if (hovered) {
        const double t = double(ImGui::GetIO().MousePos.x - origin.x) / width;
        const double depth = lo * std::pow(hi / lo, std::clamp(t, 0.0, 1.0));
        const char* mode = depth < d.reconstructionNearer ? kModeName[0] : depth > d.lowPassFarther ? kModeName[1] : kModeName[2];
        ImGui::SetTooltip("depth %.3f bounding radii: a kernel there takes %s", depth / radius, mode);
    }
}

// Cost beside error: the Measure button (or the progress of a measurement) and a row per filter measured.
void drawCostColumn(EditorState& state, const FiltersView& view, FiltersChanges& changes) {
    textWrapped("cost and error in this view");
    if (!renderer::hasGroundTruth(state.settings)) {
        textDisabledWrapped("no ground truth with surface splats");
        return;
    }
    if (view.measuring) {
        char label[48];
        double progress = view.truthProgress;
        std::snprintf(label, sizeof label, "ground truth %.0f %%", 100.0 * view.truthProgress);
        if (view.settingsToMeasure > 0) {
            progress = double(view.measurements.size()) / double(view.settingsToMeasure);
            std::snprintf(label, sizeof label, "timed %zu of %zu", view.measurements.size(), view.settingsToMeasure);
        }
        ImGui::ProgressBar(float(std::clamp(progress, 0.0, 1.0)), ImVec2(-ImGui::GetFontSize() * 5.0f, 0.0f),
                           label);
        ImGui::SameLine();
        changes.cancel = ImGui::Button("Cancel");
    } else {
        ImGui::BeginDisabled(!view.plane);
        changes.measure = ImGui::Button("Measure");
        ImGui::EndDisabled();
        hint("Times each filter x compositing mode on the whole view (median and p10-p90 of the Repeats frames)\n"
             "and compares the view's centre crop with the ground truth: the exact integral along Gaussian-weighted\n"
             "rays, computed on the CPU (seconds to minutes, cached on disk for the next time). With Settings >\n"
             "Image-aligned slabs on, the slabs in force too (a hexagon; post-classified: against the truth of\n"
             "post-classification). The chart marks the Pareto front (ringed gold: no other setting is both faster\n"
             "and closer) and the settings in force (white)");
        sameLineIfFits("repeats 00", 2.0f * ImGui::GetStyle().FramePadding.x);
        ImGui::SetNextItemWidth(ImGui::CalcTextSize("repeats 00").x + 2.0f * ImGui::GetStyle().FramePadding.x);
        if (numberField("##repeats", state.measureRepeats,
                        [&] { return ImGui::SliderInt("##repeats", &state.measureRepeats, 1, 20, "repeats %d"); }))
            state.measureRepeats = std::clamp(state.measureRepeats, 1, 100);
        numberHint("Timed frames per setting: more give a steadier median and a truer p10-p90 spread");
        if (view.measurementsStale && !view.measurements.empty()) {
            sameLineIfFits("(for an earlier view)");
            ImGui::TextDisabled("(for an earlier view)");
        }
    }
    if (view.measurements.empty()) return;
    // The chart over most of the height left, the figures in a scrolling list under it (two lines a
    // setting, so that a narrow column cuts nothing off).
    const float font = ImGui::GetFontSize(), avail = ImGui::GetContentRegionAvail().y;
    const float chartHeight = std::max(7.0f * font, 0.62f * avail);
    changes.chart = drawSpeedErrorChart(view.measurements, state.settings, chartHeight, view.slabsInForce);
    const float listHeight = std::max(4.0f * font, ImGui::GetContentRegionAvail().y - ImGui::GetStyle().ItemSpacing.y);
    if (ImGui::BeginChild("##cost_list", ImVec2(0.0f, listHeight))) {
        for (size_t i = 0; i < view.measurements.size(); ++i) {
            const renderer::FilterMeasurement& m = view.measurements[i];
            const PointStyle style = pointStyle(m);
            textColouredWrapped(ImVec4(style.r / 255.0f, style.g / 255.0f, style.b / 255.0f, 1.0f), "%s%s%s",
                                settingLabel(m).c_str(), changes.chart->points[i].pareto ? "  (Pareto)" : "",
                                changes.chart->points[i].current ? "  (in force)" : "");
            textWrapped("  %.1f ms (p10 %.1f, p90 %.1f), %.2f dB (%.4f)", m.frameMs, m.p10Ms, m.p90Ms, m.psnrDb,
                        m.rmse);
        }
        textDisabledWrapped("error over the centre %d x %d px; %d frames timed per setting", view.cropPx, view.cropPx,
                            view.measurements.front().frames);
    }
    ImGui::EndChild();
}

// The heatmap toggle, its opacity over the image and the regime tour. Returns whether the toggle changed.
bool drawHeatmapControls(EditorState& state, const FiltersView& view) {
    bool changed = false;
    if (ImGui::Checkbox("Heatmap", &state.showHeatmap)) {
        state.settings.heatmap = state.showHeatmap;
        changed = true;
    }
    hint("The filter-mode heatmap over the image: each pixel's colour is the opacity-weighted share of the\n"
         "splats of each filter (red reconstruction, green low-pass, blue full EWA); the legend in the\n"
         "viewport gives the thresholds for the view shown");
    sameLineIfFits("opacity 0.00", 2.0f * ImGui::GetStyle().FramePadding.x);
    ImGui::BeginDisabled(!state.showHeatmap);
    ImGui::SetNextItemWidth(-FLT_MIN);   // to the column's edge
    float opacity = float(state.heatmapOpacity);
    if (numberField("##heatmap_opacity", opacity, [&] {
            return ImGui::SliderFloat("##heatmap_opacity", &opacity, 0.0f, 1.0f, "opacity %.2f");
        }))
        state.heatmapOpacity = double(std::clamp(opacity, 0.0f, 1.0f));
    numberHint("How much of the heatmap over the image: 0 the image only, 1 the heatmap only");
    ImGui::EndDisabled();
    // The tour moves through the depths where the filter changes: none in an orthographic view.
    const bool canTour = view.plane && !view.plane->orthographic;
    ImGui::BeginDisabled(!canTour && !state.tour);
    if (state.tour ? ImGui::Button("Stop tour") : ImGui::Button("Regime tour")) {
        if (state.tour) {
            state.tour.reset();
        } else {
            const renderer::AdaptiveThresholds t = renderer::adaptiveThresholds(view.spacing, *view.plane, state.settings);
            const renderer::FilterDepths d = renderer::filterDepths(t, *view.plane);
            const double r = std::max(view.radius, 1e-12);
            state.tour = makeRegimeTour(state.camera.distance, d.reconstructionNearer / r, d.lowPassFarther / r);
            if (!state.showHeatmap) state.showHeatmap = state.settings.heatmap = changed = true;
        }
    }
    hint("Dolly the camera from near to far and back over a few seconds, with the heatmap on, to watch\n"
         "regions change filter; any camera input of yours stops it (orthographic views: one filter, no tour)");
    ImGui::EndDisabled();
    return changed;
}

} // namespace

FiltersChanges drawFiltersPanel(EditorState& state, const FiltersView& view) {
    renderer::SplatSettings& s = state.settings;
    FiltersChanges changes;
    bool& changed = changes.settingsChanged;
    if (!ImGui::BeginTable("##filters", 3, ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_SizingStretchSame))
        return changes;
    ImGui::TableNextRow();

    // What: the toggle, the legend, the filter in force, and the shares of patches and splats.
    ImGui::TableNextColumn();
    changed = drawHeatmapControls(state, view);
    if (s.filter == renderer::FilterMode::Adaptive)
        textWrapped("filter  adaptive, per patch of %d x %d slice voxels", s.patchSize, s.patchSize);
    else
        textWrapped("filter  %s for every splat (forced); adaptive would choose:",
                           renderer::filterModeName(s.filter));
    if (view.patches) shareText("patches", *view.patches);
    else ImGui::TextDisabled("patches  (no volume)");
    if (view.frame.hasCounters) {
        const auto& c = view.frame.counters;
        shareText("splats drawn", {c.drawnPerMode[0], c.drawnPerMode[1], c.drawnPerMode[2]});
    } else {
        textDisabledWrapped("splats per filter: turn on Settings > GPU counters");
    }

    // Why: the depths where the filter changes, against the volume's depths.
    ImGui::TableNextColumn();
    if (!view.plane) {
        ImGui::TextDisabled("no volume loaded");
        ImGui::TableNextColumn();
        drawCostColumn(state, view, changes);
        ImGui::EndTable();
        return changes;
    }
    const renderer::AdaptiveThresholds t = renderer::adaptiveThresholds(view.spacing, *view.plane, s);
    const renderer::FilterDepths d = renderer::filterDepths(t, *view.plane);
    const glm::dvec2 depths = view.plane->depthRange(view.dims, view.origin, view.spacing);
    const double r = std::max(view.radius, 1e-12);
    textWrapped("A kernel of sigma %.3g covers sigma x f / depth pixels: reconstruction only above %.2f px "
                       "(1 / c_min), low-pass only below %.2f px (1 / c_max), full EWA between.",
                       t.sigmaMin, t.reconstructionAbovePx, t.lowPassBelowPx);
    if (view.plane->orthographic) {
        const renderer::FilterMode one = renderer::classifyDepth(1.0, *view.plane, t);
        textWrapped("orthographic: %.2f px a kernel at every depth, so %s everywhere", t.sigmaMin * view.plane->fPx,
                    renderer::filterModeName(one));
    } else {
        textWrapped("volume (bracket): %.2f .. %.2f bounding radii from the eye", depths.x / r, depths.y / r);
        drawDepthBar(d, depths, r);
        char nearer[64], farther[64];
        std::snprintf(nearer, sizeof nearer, "reconstruction nearer than %.2f", d.reconstructionNearer / r);
        std::snprintf(farther, sizeof farther, "low-pass farther than %.2f", d.lowPassFarther / r);
        if (ImGui::CalcTextSize(nearer).x <= ImGui::GetContentRegionAvail().x) {
            ImGui::TextColored(kModeColour[0], "%s", nearer);
            sameLineIfFits(farther);
        } else {
            textColouredWrapped(kModeColour[0], "%s", nearer);
        }
        textColouredWrapped(kModeColour[1], "%s", farther);
    }
    if (s.hysteresis > 0.0) {
        textDisabledWrapped("hysteresis %.2f: a patch keeps its filter until a threshold is passed by %.0f %%",
                            s.hysteresis, 100.0 * s.hysteresis);
    }

    // Cost: each filter's time and error, on request.
    ImGui::TableNextColumn();
    drawCostColumn(state, view, changes);
    ImGui::EndTable();
    return changes;
}

} // namespace ui
