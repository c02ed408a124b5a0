// The footprint inspector's inset (footprint_inspector.h).
#include "ui/footprint_inspector.h"

#include "renderer/math/ewa.h"
#include "filter_colours.h"
#include "widgets.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace ui {

namespace {

// The heatmap's hues, lightened for the dark inset (filter_colours.h): reconstruction, low-pass, EWA.
ImU32 filterColour(size_t mode) { return ImGui::ColorConvertFloat4ToU32(kModeColour[mode]); }

void drawEllipse(ImDrawList* draw, ImVec2 centre, const renderer::Ellipse& e, ImU32 colour) {
    constexpr int kSegments = 64;
    std::array<ImVec2, kSegments> points;
    const double c = std::cos(e.angleRad), s = std::sin(e.angleRad);
    for (int i = 0; i < kSegments; ++i) {
        const double t = 2.0 * M_PI * i / kSegments;
        const double x = e.semiAxesPx.x * std::cos(t), y = e.semiAxesPx.y * std::sin(t);
        points[size_t(i)] = ImVec2(centre.x + float(c * x - s * y), centre.y + float(s * x + c * y));
    }
    draw->AddPolyline(points.data(), kSegments, colour, ImDrawFlags_Closed, 1.5f);
}

} // namespace

FootprintInset footprintInset(const renderer::FootprintInspection& f, float sidePx) {
    FootprintInset inset;
    inset.sidePx = sidePx;
    const std::array<const glm::dmat2*, 3> variances{&f.reconstruction, &f.lowPass, &f.ewa};
    for (size_t k = 0; k < 3; ++k) inset.ellipses[k] = renderer::ellipseOf(*variances[k], f.cutoffSigmas);
    double largest = 0.0;
    for (const renderer::Ellipse& e : inset.ellipses) largest = std::max(largest, e.semiAxesPx.x);
    const double fit = 0.45 * sidePx / std::max(largest, 1e-9);
    inset.magnification = fit >= 1.0 ? std::floor(fit) : fit;
    for (renderer::Ellipse& e : inset.ellipses) e.semiAxesPx *= inset.magnification;
    return inset;
}

void drawFootprintInspector(const renderer::FootprintInspection& f, float value, float topRightX, float topRightY) {
    const float side = ImGui::GetFontSize() * 14.0f, pad = ImGui::GetFontSize() * 0.5f;
    const FootprintInset inset = footprintInset(f, side);
    const ImVec2 min(topRightX - side - pad, topRightY + pad), max(topRightX - pad, topRightY + pad + side);
    const ImVec2 centre(0.5f * (min.x + max.x), 0.5f * (min.y + max.y));
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(min, max, IM_COL32(12, 12, 16, 235));
    draw->PushClipRect(min, max, true);
    // The image's pixel grid around the centre: a line on each pixel edge, where the squares are big
    // enough to see.
    const double m = inset.magnification;
    if (m >= 4.0) {
        const ImU32 grid = IM_COL32(255, 255, 255, 28);
        const double x0 = f.centrePx.x - 0.5 * side / m, y0 = f.centrePx.y - 0.5 * side / m;
        for (double px = std::ceil(x0); px < x0 + side / m; px += 1.0) {
            const float x = centre.x + float((px - f.centrePx.x) * m);
            draw->AddLine(ImVec2(x, min.y), ImVec2(x, max.y), grid);
        }
        for (double py = std::ceil(y0); py < y0 + side / m; py += 1.0) {
            const float y = centre.y + float((py - f.centrePx.y) * m);
            draw->AddLine(ImVec2(min.x, y), ImVec2(max.x, y), grid);
        }
    }
    const renderer::FilterMode drawn = f.patchFilter;
    for (size_t k = 0; k < 3; ++k) {
        const bool used = size_t(drawn) == k;
        drawEllipse(draw, centre, inset.ellipses[k], used ? filterColour(k) : (filterColour(k) & 0x90FFFFFFu));
    }
    draw->AddLine(ImVec2(centre.x - 4, centre.y), ImVec2(centre.x + 4, centre.y), IM_COL32(255, 255, 255, 160));
    draw->AddLine(ImVec2(centre.x, centre.y - 4), ImVec2(centre.x, centre.y + 4), IM_COL32(255, 255, 255, 160));
    draw->PopClipRect();
    draw->AddRect(min, max, IM_COL32(255, 255, 255, 60));

    // The figures, under the inset: radii at the cutoff in image pixels, and the classifier's test.
    const auto radii = [&](const glm::dmat2& v) {
        const renderer::Ellipse e = renderer::ellipseOf(v, f.cutoffSigmas);
        char text[64];
        std::snprintf(text, sizeof text, "%.2f x %.2f px", e.semiAxesPx.x, e.semiAxesPx.y);
        return std::string(text);
    };
    const renderer::AdaptiveThresholds& t = f.thresholds;
    const std::array<std::string, 3> names{"reconstruction " + radii(f.reconstruction),
                                           "low-pass       " + radii(f.lowPass), "EWA            " + radii(f.ewa)};
    char lines[4][160];
    std::snprintf(lines[0], sizeof lines[0], "voxel (%d, %d, %d) value %.5g  depth %.4g  |J| %.4g  (x%.3g)",
                  f.voxel.x, f.voxel.y, f.voxel.z, double(value), f.depth, f.jacobianDet, m);
    std::snprintf(lines[1], sizeof lines[1], "radii at %.1f sigmas:", f.cutoffSigmas);
    std::snprintf(lines[2], sizeof lines[2], "R_k %.3g..%.3g px: reconstruction above %.3g, low-pass below %.3g",
                  f.kernelPx.x, f.kernelPx.y, t.reconstructionAbovePx, t.lowPassBelowPx);
    std::snprintf(lines[3], sizeof lines[3], "drawn with: %s", renderer::filterModeName(drawn));
    const float line = ImGui::GetTextLineHeightWithSpacing();
    float width = side;
    for (const char* l : {lines[0], lines[2]}) width = std::max(width, ImGui::CalcTextSize(l).x + 2 * pad);
    const ImVec2 textMin(max.x - width, max.y), textMax(max.x, max.y + 7.0f * line + pad);
    draw->AddRectFilled(textMin, textMax, IM_COL32(12, 12, 16, 235));
    ImVec2 at(textMin.x + pad, textMin.y + 0.5f * pad);
    const ImU32 text = ImGui::GetColorU32(ImGuiCol_Text);
    const auto put = [&](const char* s, ImU32 colour) {
        draw->AddText(at, colour, s);
        at.y += line;
    };
    put(lines[0], text);
    put(lines[1], text);
    for (size_t k = 0; k < 3; ++k) put(names[k].c_str(), filterColour(k));
    put(lines[2], text);
    put(lines[3], filterColour(std::min<size_t>(size_t(drawn), 2)));
}

} // namespace ui
