// The heatmap legend's figures (from the classifier's own functions) and its box in the viewport.
#include "ui/heatmap_legend.h"

#include "filter_colours.h"
#include "renderer/math/classifier.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ui {

namespace {

std::string format(const char* pattern, double a, double b = 0.0) {
    char text[128];
    std::snprintf(text, sizeof text, pattern, a, b);
    return text;
}

} // namespace

HeatmapLegend heatmapLegend(glm::dvec3 spacing, double radius, const renderer::ImagePlane& plane,
                            const renderer::SplatSettings& settings, double fovYDeg) {
    const renderer::AdaptiveThresholds t = renderer::adaptiveThresholds(spacing, plane, settings);
    const renderer::FilterDepths d = renderer::filterDepths(t, plane);
    const double r = std::max(radius, 1e-12);
    HeatmapLegend legend;
    legend.reconstructionAbovePx = t.reconstructionAbovePx;
    legend.lowPassBelowPx = t.lowPassBelowPx;
    legend.reconstructionNearer = d.reconstructionNearer / r;
    legend.lowPassFarther = d.lowPassFarther / r;
    legend.orthographic = plane.orthographic;
    legend.fovYDeg = fovYDeg;
    if (plane.orthographic) { // one size on screen at every depth: no depth thresholds
        legend.rows = {format("reconstruction   sigma above %.2f px", t.reconstructionAbovePx),
                       format("EWA              %.2f .. %.2f px", t.lowPassBelowPx, t.reconstructionAbovePx),
                       format("low-pass         sigma below %.2f px", t.lowPassBelowPx)};
        legend.footer =
            format("orthographic: every kernel is %.2f px, one filter everywhere", t.sigmaMin * plane.fPx);
        return legend;
    }
    legend.rows = {
        format("reconstruction   sigma above %.2f px, nearer than %.2f", t.reconstructionAbovePx,
               legend.reconstructionNearer),
        format("EWA              sigma %.2f .. %.2f px, between", t.lowPassBelowPx, t.reconstructionAbovePx),
        format("low-pass         sigma below %.2f px, farther than %.2f", t.lowPassBelowPx,
               legend.lowPassFarther)};
    legend.footer = format("depths from the eye in bounding radii, fov %.0f deg, %.0f px high", fovYDeg,
                           double(plane.height));
    return legend;
}

void drawHeatmapLegend(const HeatmapLegend& legend, float minX, float minY, float maxX, float maxY) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const float font = ImGui::GetFontSize(), pad = font * 0.4f, swatch = font * 0.8f;
    float width = ImGui::CalcTextSize(legend.footer.c_str()).x;
    for (const std::string& row : legend.rows)
        width = std::max(width, swatch + pad + ImGui::CalcTextSize(row.c_str()).x);
    const float height = font * 4.0f + pad * 5.0f;
    const ImVec2 lo(minX + pad, std::max(minY, maxY - height - 2.0f * pad));
    const ImVec2 hi(std::min(maxX, lo.x + width + 2.0f * pad), lo.y + height);
    draw->PushClipRect(ImVec2(minX, minY), ImVec2(maxX, maxY), true);
    draw->AddRectFilled(lo, hi, IM_COL32(0, 0, 0, 190), 3.0f);
    const int order[3] = {0, 2, 1}; // nearest regime first
    float y = lo.y + pad;
    for (int i = 0; i < 3; ++i, y += font + pad) {
        draw->AddRectFilled(ImVec2(lo.x + pad, y + (font - swatch) * 0.5f),
                            ImVec2(lo.x + pad + swatch, y + (font + swatch) * 0.5f),
                            kHeatmapColour[order[i]]);
        draw->AddText(ImVec2(lo.x + 2.0f * pad + swatch, y), ImGui::GetColorU32(kModeColour[order[i]]),
                      legend.rows[size_t(i)].c_str());
    }
    draw->AddText(ImVec2(lo.x + pad, y), IM_COL32(200, 200, 200, 255), legend.footer.c_str());
    draw->PopClipRect();
}

} // namespace ui
