// Speed against error as a chart (speed_error_chart.h).
#include "ui/speed_error_chart.h"

#include "renderer/oracle/speed_error.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace ui {

namespace {

// Ticks at the round step (1, 2 or 5 x 10^k) that gives about `count` of them between lo and hi.
std::vector<double> roundTicks(double lo, double hi, int count) {
    const double raw = (hi - lo) / std::max(count, 1);
    const double decade = std::pow(10.0, std::floor(std::log10(raw)));
    double step = decade;
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * decade >= raw) {
            step = m * decade;
            break;
        }
    std::vector<double> ticks;
    for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step)
        ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
    return ticks;
}

} // namespace

double SpeedErrorChart::yAt(double db) const {
    const double t = std::clamp((db - psnrDb.lo) / (psnrDb.hi - psnrDb.lo), 0.0, 1.0); // +inf: 1
    return bottom - t * (bottom - top);
}

SpeedErrorChart layoutSpeedErrorChart(std::span<const renderer::FilterMeasurement> points,
                                      const renderer::SplatSettings* current, double left, double top,
                                      double right, double bottom, bool slabsInForce) {
    SpeedErrorChart c;
    c.left = left, c.top = top, c.right = std::max(right, left + 1.0), c.bottom = std::max(bottom, top + 1.0);
    // 1. Axes: time from 0 to 8 % past the slowest p90; PSNR 1 dB either side of the finite values.
    double slowest = 0.0, lowDb = std::numeric_limits<double>::infinity(), highDb = -lowDb;
    for (const renderer::FilterMeasurement& m : points) {
        slowest = std::max({slowest, m.p90Ms, m.frameMs});
        if (std::isfinite(m.psnrDb)) lowDb = std::min(lowDb, m.psnrDb), highDb = std::max(highDb, m.psnrDb);
    }
    if (!(highDb >= lowDb)) lowDb = 0.0, highDb = 60.0; // no finite PSNR: every image identical
    c.timeMs = {0.0, slowest > 0.0 ? 1.08 * slowest : 1.0, {}};
    c.psnrDb = {std::floor(lowDb) - 1.0, std::ceil(highDb) + 1.0, {}};
    c.timeMs.ticks = roundTicks(c.timeMs.lo, c.timeMs.hi, 5);
    c.psnrDb.ticks = roundTicks(c.psnrDb.lo, c.psnrDb.hi, 4);
    // 2. Points, the front and the current setting.
    const std::vector<bool> front = renderer::paretoFront(points);
    for (size_t i = 0; i < points.size(); ++i) {
        const renderer::FilterMeasurement& m = points[i];
        c.points.push_back({c.xAt(m.frameMs), c.xAt(m.p10Ms), c.xAt(m.p90Ms), c.yAt(m.psnrDb), front[i],
                            current && current->filter == m.filter && current->compositing == m.compositing &&
                                (m.slabThickness > 0.0) == slabsInForce});
        if (front[i]) c.front.push_back(i);
    }
    const auto truth = [&](size_t i) { return renderer::groundTruthKind(points[i]); };
    std::sort(c.front.begin(), c.front.end(), [&](size_t a, size_t b) {
        if (truth(a) != truth(b)) return truth(a) < truth(b);
        return points[a].frameMs != points[b].frameMs ? points[a].frameMs < points[b].frameMs
                                                      : points[a].psnrDb < points[b].psnrDb;
    });
    return c;
}

std::string settingLabel(const renderer::FilterMeasurement& m) {
    if (m.slabThickness > 0.0) {
        char slabs[64];
        std::snprintf(slabs, sizeof slabs, ", image-aligned slabs %g%s", m.slabThickness,
                      m.postClassified ? ", post-classified" : "");
        return renderer::filterModeName(m.filter) + std::string(slabs);
    }
    return std::string(renderer::filterModeName(m.filter)) + ", " + renderer::compositingName(m.compositing);
}

PointStyle pointStyle(const renderer::FilterMeasurement& m) {
    // The Filters panel's hues (filter_colours.h); adaptive, a mix of the three, light grey.
    static constexpr unsigned char rgb[4][3] = {
        {255, 77, 77}, {77, 255, 77}, {102, 128, 255}, {220, 220, 220}};
    const size_t f = std::min(size_t(m.filter), size_t(3));
    PointStyle::Shape shape = PointStyle::Circle;
    if (m.compositing == renderer::Compositing::SheetBackToFront) shape = PointStyle::Square;
    if (m.compositing == renderer::Compositing::SheetFrontToBack) shape = PointStyle::Diamond;
    if (m.compositing == renderer::Compositing::XRay) shape = PointStyle::Triangle;
    if (m.slabThickness > 0.0) shape = PointStyle::Hexagon;
    return {rgb[f][0], rgb[f][1], rgb[f][2], shape};
}

SpeedErrorChart drawSpeedErrorChart(std::span<const renderer::FilterMeasurement> points,
                                    const renderer::SplatSettings& current, float height, bool slabsInForce) {
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = std::max(ImGui::GetContentRegionAvail().x, 1.0f), font = ImGui::GetFontSize();
    ImGui::Dummy(ImVec2(width, height));
    const bool hovered = ImGui::IsItemHovered();
    // The plot inside room for the PSNR labels on the left and the time labels below.
    const SpeedErrorChart c =
        layoutSpeedErrorChart(points, &current, origin.x + 3.0f * font, origin.y + 0.5f * font,
                              origin.x + width - 0.5f * font, origin.y + height - 2.2f * font, slabsInForce);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImU32 grey = ImGui::GetColorU32(ImGuiCol_TextDisabled), grid = IM_COL32(255, 255, 255, 30);
    const auto at = [](double x, double y) { return ImVec2(float(x), float(y)); };
    char text[48];
    // 1. Grid, ticks and axis names.
    for (double t : c.timeMs.ticks) { // labels centred on their tick, kept inside the chart's width
        draw->AddLine(at(c.xAt(t), c.top), at(c.xAt(t), c.bottom), grid);
        std::snprintf(text, sizeof text, "%g", t);
        const double w = ImGui::CalcTextSize(text).x;
        draw->AddText(
            at(std::clamp(c.xAt(t) - 0.5 * w, double(origin.x), origin.x + width - w), c.bottom + 0.1 * font),
            grey, text);
    }
    for (double t : c.psnrDb.ticks) {
        draw->AddLine(at(c.left, c.yAt(t)), at(c.right, c.yAt(t)), grid);
        std::snprintf(text, sizeof text, "%g", t);
        draw->AddText(at(c.left - ImGui::CalcTextSize(text).x - 0.3 * font, c.yAt(t) - 0.5 * font), grey,
                      text);
    }
    for (const char* xName :
         {"frame time, ms (median, p10-p90)", "ms (median, p10-p90)", "ms"}) // the longest that fits
        if (ImGui::CalcTextSize(xName).x <= c.right - c.left) {
            draw->AddText(at(0.5 * (c.left + c.right - ImGui::CalcTextSize(xName).x), c.bottom + 1.1 * font),
                          grey, xName);
            break;
        }
    draw->AddText(at(origin.x, origin.y), grey, "dB");
    draw->AddRect(at(c.left, c.top), at(c.right, c.bottom), grid);
    // 2. The Pareto front, then whiskers and markers over it.
    for (size_t i = 1; i < c.front.size(); ++i) {
        if (!renderer::sameGroundTruth(points[c.front[i - 1]], points[c.front[i]])) continue;
        const ChartPoint &a = c.points[c.front[i - 1]], &b = c.points[c.front[i]];
        draw->AddLine(at(a.x, a.y), at(b.x, b.y), IM_COL32(255, 210, 80, 200), 1.5f);
    }
    const float r = 0.3f * font;
    for (size_t i = 0; i < points.size(); ++i) {
        const ChartPoint& p = c.points[i];
        const PointStyle s = pointStyle(points[i]);
        const ImU32 colour = IM_COL32(s.r, s.g, s.b, 255);
        draw->AddLine(at(p.xLo, p.y), at(p.xHi, p.y), colour);
        draw->AddLine(at(p.xLo, p.y - r), at(p.xLo, p.y + r), colour);
        draw->AddLine(at(p.xHi, p.y - r), at(p.xHi, p.y + r), colour);
        const ImVec2 m = at(p.x, p.y);
        switch (s.shape) {
        case PointStyle::Circle:
            draw->AddCircleFilled(m, r, colour);
            break;
        case PointStyle::Square:
            draw->AddRectFilled(ImVec2(m.x - r, m.y - r), ImVec2(m.x + r, m.y + r), colour);
            break;
        case PointStyle::Diamond:
            draw->AddQuadFilled(ImVec2(m.x, m.y - 1.3f * r), ImVec2(m.x + 1.3f * r, m.y),
                                ImVec2(m.x, m.y + 1.3f * r), ImVec2(m.x - 1.3f * r, m.y), colour);
            break;
        case PointStyle::Triangle:
            draw->AddTriangleFilled(ImVec2(m.x, m.y - 1.3f * r), ImVec2(m.x + 1.2f * r, m.y + r),
                                    ImVec2(m.x - 1.2f * r, m.y + r), colour);
            break;
        case PointStyle::Hexagon:
            draw->AddNgonFilled(m, 1.2f * r, colour, 6);
            break;
        }
        if (p.pareto) draw->AddCircle(m, 1.9f * r, IM_COL32(255, 210, 80, 255), 0, 1.5f);
        if (p.current) draw->AddCircle(m, 2.8f * r, IM_COL32(255, 255, 255, 255), 0, 2.0f);
    }
    // 3. The nearest point's figures under the mouse.
    if (hovered && !points.empty()) {
        const ImVec2 mouse = ImGui::GetIO().MousePos;
        size_t nearest = 0;
        double best = std::numeric_limits<double>::infinity();
        for (size_t i = 0; i < points.size(); ++i) {
            const double d = std::hypot(c.points[i].x - mouse.x, c.points[i].y - mouse.y);
            if (d < best) best = d, nearest = i;
        }
        if (best < 3.0 * font) {
            const renderer::FilterMeasurement& m = points[nearest];
            ImGui::SetTooltip("%s\n%.2f ms median (p10 %.2f, p90 %.2f, %d frames)\n%.2f dB (RMSE %.4f)%s%s",
                              settingLabel(m).c_str(), m.frameMs, m.p10Ms, m.p90Ms, m.frames, m.psnrDb,
                              m.rmse, c.points[nearest].pareto ? "\non the Pareto front" : "",
                              c.points[nearest].current ? "\nthe settings in force" : "");
        }
    }
    return c;
}

} // namespace ui
