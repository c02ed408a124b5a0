// The 2D transfer function's section (tf2d_editor.h): its edit rules and its ImGui drawing.
#include "ui/tf2d_editor.h"

#include "renderer/model/splat_scene.h"
#include "widgets.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace ui {

namespace {

using renderer::Widget2D;
using renderer::WidgetShape;

constexpr float kHandleRadiusPx = 4.0f;
constexpr float kPickRadiusPx = 7.0f;
// New widgets' colours, in turn: skin, bone, vessel red, soft blue.
constexpr glm::dvec3 kPalette[] = {{0.90, 0.65, 0.55}, {1.00, 0.95, 0.85}, {0.85, 0.25, 0.20}, {0.40, 0.60, 0.95}};
constexpr double kNewOpacity = 0.5;

double span(const Tf2dAxes& a) { return double(a.window.hi) - double(a.window.lo); }

// A triangle's outline in canvas pixels: apex, up its left side, across its top, down its right side.
// The sides are straight in data units but curve on the sqrt axis, so they are sampled.
std::vector<ImVec2> triangleOutline(const Widget2D& w, const Rect& canvas, const Tf2dAxes& axes) {
    constexpr int kSteps = 24;
    std::vector<ImVec2> left, right;
    for (int i = 0; i <= kSteps; ++i) {
        const double s = double(i) / kSteps, magnitude = w.magnitudeTop * s * s * s * s;   // finer near the apex
        const double half = w.halfWidth * magnitude / w.magnitudeTop;
        const CanvasPoint l = tf2dToCanvas(canvas, axes, w.apex - half, magnitude);
        const CanvasPoint r = tf2dToCanvas(canvas, axes, w.apex + half, magnitude);
        left.emplace_back(l.x, l.y), right.emplace_back(r.x, r.y);
    }
    std::vector<ImVec2> outline(left.begin(), left.end());
    outline.insert(outline.end(), right.rbegin(), right.rend() - 1);   // the apex once
    return outline;
}

bool holds(const Widget2D& w, const Rect& canvas, const Tf2dAxes& axes, CanvasPoint mouse) {
    if (w.shape == WidgetShape::Rectangle) {
        const CanvasPoint a = tf2dToCanvas(canvas, axes, w.valueLo, w.magnitudeLo);
        const CanvasPoint b = tf2dToCanvas(canvas, axes, w.valueHi, w.magnitudeHi);
        return mouse.x >= a.x && mouse.x <= b.x && mouse.y <= a.y && mouse.y >= b.y;
    }
    double value = 0, magnitude = 0;
    canvasToTf2d(canvas, axes, mouse, value, magnitude);
    return renderer::widgetWeight(w, value, magnitude) > 0.0;
}

ImU32 widgetColour(const Widget2D& w, int alpha) {
    return IM_COL32(int(w.colour.r * 255.0), int(w.colour.g * 255.0), int(w.colour.b * 255.0), alpha);
}

int add(renderer::TransferFunction& tf, Widget2D w) {
    w.colour = kPalette[tf.widgets2d.size() % std::size(kPalette)];
    w.opacity = kNewOpacity;
    tf.widgets2d.push_back(w);
    return int(tf.widgets2d.size()) - 1;
}

} // namespace

CanvasPoint tf2dToCanvas(const Rect& canvas, const Tf2dAxes& axes, double value, double magnitude) {
    const double t = span(axes) > 0.0 ? (value - axes.window.lo) / span(axes) : 0.0;
    const double s = axes.maxMagnitude > 0.0 ? std::sqrt(std::clamp(magnitude / axes.maxMagnitude, 0.0, 1.0)) : 0.0;
    return {canvas.x + float(t) * canvas.w, canvas.bottom() - float(s) * canvas.h};
}

void canvasToTf2d(const Rect& canvas, const Tf2dAxes& axes, CanvasPoint p, double& value, double& magnitude) {
    value = axes.window.lo + (canvas.w > 0 ? double(p.x - canvas.x) / canvas.w : 0.0) * span(axes);
    const double s = canvas.h > 0 ? std::clamp(double(canvas.bottom() - p.y) / canvas.h, 0.0, 1.0) : 0.0;
    magnitude = axes.maxMagnitude * s * s;
}

std::vector<HandleAt> widgetHandles(const Widget2D& w, const Rect& canvas, const Tf2dAxes& axes) {
    if (w.shape == WidgetShape::Rectangle)
        return {{WidgetHandle::LowLow, tf2dToCanvas(canvas, axes, w.valueLo, w.magnitudeLo)},
                {WidgetHandle::HighLow, tf2dToCanvas(canvas, axes, w.valueHi, w.magnitudeLo)},
                {WidgetHandle::LowHigh, tf2dToCanvas(canvas, axes, w.valueLo, w.magnitudeHi)},
                {WidgetHandle::HighHigh, tf2dToCanvas(canvas, axes, w.valueHi, w.magnitudeHi)}};
    return {{WidgetHandle::Apex, tf2dToCanvas(canvas, axes, w.apex, 0.0)},
            {WidgetHandle::TopLeft, tf2dToCanvas(canvas, axes, w.apex - w.halfWidth, w.magnitudeTop)},
            {WidgetHandle::TopRight, tf2dToCanvas(canvas, axes, w.apex + w.halfWidth, w.magnitudeTop)},
            {WidgetHandle::TopEdge, tf2dToCanvas(canvas, axes, w.apex, w.magnitudeTop)}};
}

WidgetPick pickWidget(const renderer::TransferFunction& tf, const Rect& canvas, const Tf2dAxes& axes,
                      CanvasPoint mouse, float radiusPx, int selected) {
    const int n = int(tf.widgets2d.size());
    std::vector<int> order;   // the selected one, then the topmost (last drawn) first
    if (selected >= 0 && selected < n) order.push_back(selected);
    for (int i = n - 1; i >= 0; --i)
        if (i != selected) order.push_back(i);
    for (int i : order) {
        WidgetPick best;
        float bestD2 = radiusPx * radiusPx;
        for (const HandleAt& h : widgetHandles(tf.widgets2d[size_t(i)], canvas, axes)) {
            const float dx = h.at.x - mouse.x, dy = h.at.y - mouse.y, d2 = dx * dx + dy * dy;
            if (d2 <= bestD2) best = {i, h.handle}, bestD2 = d2;
        }
        if (best.index >= 0) return best;
    }
    for (int i : order)
        if (holds(tf.widgets2d[size_t(i)], canvas, axes, mouse)) return {i, WidgetHandle::Body};
    return {};
}

Widget2D draggedWidget(const Widget2D& atPress, WidgetHandle handle, const Rect& canvas, const Tf2dAxes& axes,
                       CanvasPoint press, CanvasPoint now) {
    Widget2D w = atPress;
    const float dx = now.x - press.x, dy = now.y - press.y;
    // Where the point `p` of the widget (canvas pixels at the press) is now.
    const auto moved = [&](CanvasPoint p, double& value, double& magnitude) {
        canvasToTf2d(canvas, axes, {p.x + dx, p.y + dy}, value, magnitude);
    };
    const double valueStep = canvas.w > 0 ? double(dx) / canvas.w * span(axes) : 0.0;
    double v = 0, m = 0;
    if (w.shape == WidgetShape::Rectangle) {
        const CanvasPoint lo = tf2dToCanvas(canvas, axes, atPress.valueLo, atPress.magnitudeLo);
        const CanvasPoint hi = tf2dToCanvas(canvas, axes, atPress.valueHi, atPress.magnitudeHi);
        if (handle == WidgetHandle::Body) {
            // Both corners by the same pixels, held inside the canvas's magnitudes so its height stays.
            const float up = std::clamp(dy, canvas.y - hi.y, canvas.bottom() - lo.y);
            double unused = 0;
            canvasToTf2d(canvas, axes, {lo.x, lo.y + up}, unused, w.magnitudeLo);
            canvasToTf2d(canvas, axes, {hi.x, hi.y + up}, unused, w.magnitudeHi);
            w.valueLo = atPress.valueLo + valueStep, w.valueHi = atPress.valueHi + valueStep;
            return w;
        }
        const bool lowValue = handle == WidgetHandle::LowLow || handle == WidgetHandle::LowHigh;
        const bool lowMagnitude = handle == WidgetHandle::LowLow || handle == WidgetHandle::HighLow;
        if (handle == WidgetHandle::None) return w;
        moved({lowValue ? lo.x : hi.x, lowMagnitude ? lo.y : hi.y}, v, m);
        const double otherValue = lowValue ? atPress.valueHi : atPress.valueLo;
        const double otherMagnitude = lowMagnitude ? atPress.magnitudeHi : atPress.magnitudeLo;
        w.valueLo = std::min(v, otherValue), w.valueHi = std::max(v, otherValue);
        w.magnitudeLo = std::min(m, otherMagnitude), w.magnitudeHi = std::max(m, otherMagnitude);
        return w;
    }
    // A triangle's width and top keep a floor: a pixel's worth, so it stays visible and pickable.
    const double minWidth = canvas.w > 0 ? span(axes) / canvas.w : 1e-9;
    const double minTop = axes.maxMagnitude > 0 && canvas.h > 0 ? axes.maxMagnitude / double(canvas.h * canvas.h) : 1e-9;
    switch (handle) {
    case WidgetHandle::Body:
    case WidgetHandle::Apex: w.apex = atPress.apex + valueStep; break;
    case WidgetHandle::TopLeft:
    case WidgetHandle::TopRight:
        moved(tf2dToCanvas(canvas, axes,
                           atPress.apex + (handle == WidgetHandle::TopLeft ? -atPress.halfWidth : atPress.halfWidth),
                           atPress.magnitudeTop),
              v, m);
        w.halfWidth = std::max(std::abs(v - atPress.apex), minWidth);
        w.magnitudeTop = std::max(m, minTop);
        break;
    case WidgetHandle::TopEdge:
        moved(tf2dToCanvas(canvas, axes, atPress.apex, atPress.magnitudeTop), v, m);
        w.magnitudeTop = std::max(m, minTop);
        break;
    default: break;
    }
    return w;
}

int addRectangle(renderer::TransferFunction& tf, const Tf2dAxes& axes) {
    Widget2D w;
    w.shape = WidgetShape::Rectangle;
    w.valueLo = axes.window.lo + 0.4 * span(axes), w.valueHi = axes.window.lo + 0.6 * span(axes);
    w.magnitudeLo = axes.maxMagnitude * 0.2 * 0.2, w.magnitudeHi = axes.maxMagnitude * 0.6 * 0.6;
    return add(tf, w);
}

int addTriangle(renderer::TransferFunction& tf, const Tf2dAxes& axes) {
    Widget2D w;
    w.shape = WidgetShape::Triangle;
    w.apex = axes.window.lo + 0.5 * span(axes), w.halfWidth = 0.1 * span(axes);
    w.magnitudeTop = axes.maxMagnitude * 0.5 * 0.5;
    return add(tf, w);
}

bool removeWidget(renderer::TransferFunction& tf, int index) {
    if (index < 0 || size_t(index) >= tf.widgets2d.size()) return false;
    tf.widgets2d.erase(tf.widgets2d.begin() + index);
    return true;
}

bool drawTf2dSection(renderer::TransferFunction& tf, Tf2dEdit& edit, const Tf2dView& view) {
    char label[64];
    std::snprintf(label, sizeof label, "2D transfer function (%zu)###tf2d", tf.widgets2d.size());
    const bool open = ImGui::CollapsingHeader(label, tf.widgets2d.empty() ? 0 : ImGuiTreeNodeFlags_DefaultOpen);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("2D transfer function: widgets over value x gradient magnitude that, when any is set,\n"
                          "give each voxel its colour and opacity instead of the curves above; click to %s",
                          open ? "close" : "open");
    if (!open) return false;
    const Tf2dAxes& axes = view.axes;
    if (!(axes.maxMagnitude > 0.0) || !(axes.window.hi > axes.window.lo)) {
        ImGui::TextDisabled(tf.widgets2d.empty() ? "Waits for the volume's gradients"
                                                 : "Set; applies once the volume's gradients are computed");
        return false;
    }
    if (edit.selected >= int(tf.widgets2d.size())) edit.selected = -1;
    bool changed = false;

    // 1. The canvas: a left press picks a widget or handle and drags it; a right click removes one.
    const auto [canvas, mouse, moved] = canvasInput("##tf2d_canvas", ImGui::GetFontSize() * 9.0f);
    if (ImGui::IsItemActivated() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        const WidgetPick pick = pickWidget(tf, canvas, axes, mouse, kPickRadiusPx, edit.selected);
        edit.selected = pick.index;
        edit.handle = pick.handle;
        if (pick.index >= 0) edit.atPress = tf.widgets2d[size_t(pick.index)], edit.press = mouse;
    } else if (ImGui::IsItemActive() && ImGui::IsMouseDown(ImGuiMouseButton_Left) && edit.selected >= 0 &&
               edit.handle != WidgetHandle::None && moved) {
        const Widget2D next = draggedWidget(edit.atPress, edit.handle, canvas, axes, edit.press, mouse);
        Widget2D& w = tf.widgets2d[size_t(edit.selected)];
        changed = changed || next != w;
        w = next;
    }
    if (!ImGui::IsItemActive()) edit.handle = WidgetHandle::None;
    if (ImGui::IsItemClicked(ImGuiMouseButton_Right) &&
        removeWidget(tf, pickWidget(tf, canvas, axes, mouse, kPickRadiusPx, edit.selected).index)) {
        edit.selected = -1;
        changed = true;
    }
    if (ImGui::IsItemHovered()) {
        double value = 0, magnitude = 0;
        canvasToTf2d(canvas, axes, mouse, value, magnitude);
        const WidgetPick over = pickWidget(tf, canvas, axes, mouse, kPickRadiusPx, edit.selected);
        ImGui::SetTooltip("value %.5g, |gradient| %.4g per world unit: opacity %.3g\n%s", value, magnitude,
                          renderer::evaluate2d(tf, value, magnitude).a,
                          over.index < 0                        ? "add a rectangle or a triangle below"
                          : over.handle == WidgetHandle::Body ? "drag to move, right-click to remove"
                                                               : "drag to resize, right-click to remove");
    }

    // 2. Drawn: the histogram (log counts, grey), the widgets (filled with their colour, the selected one
    //    outlined brighter) and the handles.
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->PushClipRect(ImVec2(canvas.x, canvas.y), ImVec2(canvas.right(), canvas.bottom()), true);
    draw->AddRectFilled(ImVec2(canvas.x, canvas.y), ImVec2(canvas.right(), canvas.bottom()),
                        ImGui::GetColorU32(ImGuiCol_FrameBg));
    if (view.histogram && view.histogram->size() == size_t(renderer::kTf2dCells)) {
        // Two value bins a column and, down a column, runs of one grey level a rectangle: at most 8192
        // rectangles, so the panel stays within ImGui's 16-bit vertex indices.
        constexpr int kPair = 2, kLevels = 24;
        const auto count = [&](int k, int j) {
            uint64_t c = 0;
            for (int q = k; q < k + kPair; ++q) c += (*view.histogram)[size_t(q * renderer::kTf2dGradientBins + j)];
            return c;
        };
        double peak = 0.0;
        for (int k = 0; k < renderer::kTf2dValueBins; k += kPair)
            for (int j = 0; j < renderer::kTf2dGradientBins; ++j) peak = std::max(peak, std::log1p(double(count(k, j))));
        const double lo = view.histogramWindow.lo, w = double(view.histogramWindow.hi) - lo;
        const auto rowY = [&](int j) {   // the bottom of magnitude bin j: its first byte on the sqrt axis
            return canvas.bottom() - canvas.h * float(std::min(4 * j, 255)) / 255.0f;
        };
        for (int k = 0; k < renderer::kTf2dValueBins && peak > 0.0; k += kPair) {
            const float x0 = tf2dToCanvas(canvas, axes, lo + w * k / renderer::kTf2dValueBins, 0.0).x;
            const float x1 =
                std::max(tf2dToCanvas(canvas, axes, lo + w * (k + kPair) / renderer::kTf2dValueBins, 0.0).x, x0 + 1.0f);
            for (int j = 0; j < renderer::kTf2dGradientBins;) {
                const uint64_t c = count(k, j);
                const int level = c ? 1 + int((kLevels - 1) * std::log1p(double(c)) / peak) : 0;
                int end = j + 1;
                while (end < renderer::kTf2dGradientBins) {
                    const uint64_t e = count(k, end);
                    if ((e ? 1 + int((kLevels - 1) * std::log1p(double(e)) / peak) : 0) != level) break;
                    ++end;
                }
                if (level > 0) {
                    const int grey = 40 + 200 * level / kLevels;
                    draw->AddRectFilled(ImVec2(x0, rowY(end)), ImVec2(x1, rowY(j)), IM_COL32(grey, grey, grey, 255));
                }
                j = end;
            }
        }
    }
    for (size_t i = 0; i < tf.widgets2d.size(); ++i) {
        const Widget2D& w = tf.widgets2d[i];
        const bool selected = int(i) == edit.selected;
        const ImU32 fill = widgetColour(w, int(40 + 110 * w.opacity));
        const ImU32 line = selected ? ImGui::GetColorU32(ImGuiCol_CheckMark) : widgetColour(w, 255);
        if (w.shape == WidgetShape::Rectangle) {
            const CanvasPoint a = tf2dToCanvas(canvas, axes, w.valueLo, w.magnitudeHi);
            const CanvasPoint b = tf2dToCanvas(canvas, axes, w.valueHi, w.magnitudeLo);
            draw->AddRectFilled(ImVec2(a.x, a.y), ImVec2(b.x, b.y), fill);
            draw->AddRect(ImVec2(a.x, a.y), ImVec2(b.x, b.y), line, 0.0f, 0, selected ? 2.0f : 1.5f);
        } else {
            const std::vector<ImVec2> outline = triangleOutline(w, canvas, axes);
            // Star-shaped from the middle of its top edge (not convex on the sqrt axis): a fan from there.
            const CanvasPoint top = tf2dToCanvas(canvas, axes, w.apex, w.magnitudeTop);
            for (size_t k = 0; k + 1 < outline.size(); ++k)
                draw->AddTriangleFilled(ImVec2(top.x, top.y), outline[k], outline[k + 1], fill);
            draw->AddPolyline(outline.data(), int(outline.size()), line, ImDrawFlags_Closed, selected ? 2.0f : 1.5f);
        }
        for (const HandleAt& h : widgetHandles(w, canvas, axes))
            draw->AddRectFilled(ImVec2(h.at.x - kHandleRadiusPx, h.at.y - kHandleRadiusPx),
                                ImVec2(h.at.x + kHandleRadiusPx, h.at.y + kHandleRadiusPx),
                                selected ? IM_COL32(255, 255, 255, 255) : IM_COL32(200, 200, 200, 160));
    }
    draw->PopClipRect();
    ImGui::PushTextWrapPos(0.0f);   // the panel may be narrow: wrap, do not cut
    ImGui::TextDisabled("Value across (the window), |gradient| up (sqrt axis, 0 .. %.4g per world unit)",
                        axes.maxMagnitude);
    ImGui::PopTextWrapPos();

    // 3. Add, remove, and the selected widget's colour and opacity.
    if (ImGui::Button("Add rectangle")) edit.selected = addRectangle(tf, axes), changed = true;
    hint("A rectangle: weight 1 over a range of values and of gradient magnitudes");
    ImGui::SameLine();
    if (ImGui::Button("Add triangle")) edit.selected = addTriangle(tf, axes), changed = true;
    hint("A triangle (Kniss's boundary widget): its apex at a value with no gradient, widening with the\n"
         "gradient; weight 1 on its centre line, 0 at its sides. Selects the boundary around that value");
    if (edit.selected >= 0) {
        Widget2D& w = tf.widgets2d[size_t(edit.selected)];
        ImGui::SameLine();
        if (ImGui::Button("Remove")) {
            removeWidget(tf, edit.selected);
            edit.selected = -1;
            return true;
        }
        float rgb[3] = {float(w.colour.r), float(w.colour.g), float(w.colour.b)};
        if (ImGui::ColorEdit3("Colour##tf2d", rgb, ImGuiColorEditFlags_Float)) {
            w.colour = glm::clamp(glm::dvec3(rgb[0], rgb[1], rgb[2]), 0.0, 1.0);
            changed = true;
        }
        float opacity = float(w.opacity);
        if (ImGui::SliderFloat("Opacity##tf2d", &opacity, 0.0f, 1.0f, "%.3f")) {
            w.opacity = std::clamp(double(opacity), 0.0, 1.0);
            changed = true;
        }
        hint("The widget's opacity at weight 1 (extinction per voxel length at density 1, as the curve's)");
    } else if (!tf.widgets2d.empty()) {
        ImGui::TextDisabled("Click a widget to edit its colour and opacity");
    }
    if (!tf.widgets2d.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("The widgets give each voxel its colour and opacity; the curves above apply "
                            "again once none is left");
        ImGui::PopTextWrapPos();
    }
    return changed;
}

} // namespace ui
