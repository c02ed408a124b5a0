// The gradient opacity curve (gradient_opacity_curve.h): its edit rules and its ImGui section.
#include "ui/gradient_opacity_curve.h"

#include "renderer/math/shading.h"
#include "widgets.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace ui {

namespace {

constexpr float kPointRadiusPx = 4.5f;
constexpr float kPickRadiusPx = 8.0f;
// "Fade insides": 0 at no gradient up to 1 at this share of the largest magnitude.
constexpr double kFadeInsidesShare = 0.1;

// 0..1 across for a magnitude, and back (sqrt(|g| / max): the magnitude byte's scale).
double across(double magnitude, double maxMagnitude) {
    return maxMagnitude > 0.0 ? std::sqrt(std::clamp(magnitude / maxMagnitude, 0.0, 1.0)) : 0.0;
}

} // namespace

CanvasPoint gradientToCanvas(const Rect& canvas, double magnitude, double factor, double maxMagnitude) {
    return {canvas.x + float(across(magnitude, maxMagnitude)) * canvas.w,
            canvas.bottom() - float(std::clamp(factor, 0.0, 1.0)) * canvas.h};
}

void canvasToGradient(const Rect& canvas, CanvasPoint p, double maxMagnitude, double& magnitude,
                      double& factor) {
    // The opacity curve's vertical rules: snap to 0 and 1 near the edges.
    double unused = 0.0;
    canvasToTf(canvas, p, unused, factor);
    const double t = canvas.w > 0 ? std::clamp(double(p.x - canvas.x) / canvas.w, 0.0, 1.0) : 0.0;
    magnitude = maxMagnitude * t * t;
}

int pickGradientPoint(const renderer::TransferFunction& tf, const Rect& canvas, CanvasPoint mouse,
                      double maxMagnitude, float radiusPx) {
    int best = -1;
    float bestD2 = radiusPx * radiusPx;
    for (size_t i = 0; i < tf.gradientOpacity.size(); ++i) {
        const auto& p = tf.gradientOpacity[i];
        const CanvasPoint c = gradientToCanvas(canvas, p.magnitude, p.opacity, maxMagnitude);
        const float dx = c.x - mouse.x, dy = c.y - mouse.y, d2 = dx * dx + dy * dy;
        if (d2 <= bestD2) best = int(i), bestD2 = d2;
    }
    return best;
}

int insertGradientPoint(renderer::TransferFunction& tf, double magnitude, double factor,
                        double maxMagnitude) {
    auto& pts = tf.gradientOpacity;
    if (pts.empty() && maxMagnitude > 0.0) pts = {{0.0, 1.0}, {maxMagnitude, 1.0}};
    const auto at =
        std::upper_bound(pts.begin(), pts.end(), magnitude,
                         [](double m, const renderer::GradientOpacityPoint& p) { return m < p.magnitude; });
    const renderer::GradientOpacityPoint point{std::max(magnitude, 0.0), std::clamp(factor, 0.0, 1.0)};
    const auto inserted = pts.insert(at, point); // may reallocate: begin() only after it
    return int(inserted - pts.begin());
}

void moveGradientPoint(renderer::TransferFunction& tf, int index, double magnitude, double factor) {
    auto& pts = tf.gradientOpacity;
    if (index < 0 || size_t(index) >= pts.size()) return;
    auto& p = pts[size_t(index)];
    if (std::isfinite(magnitude)) {
        const double lo = index > 0 ? pts[size_t(index) - 1].magnitude : 0.0;
        const double hi = size_t(index) + 1 < pts.size() ? pts[size_t(index) + 1].magnitude : INFINITY;
        p.magnitude = std::clamp(magnitude, lo, hi);
    }
    if (std::isfinite(factor)) p.opacity = std::clamp(factor, 0.0, 1.0);
}

bool removeGradientPoint(renderer::TransferFunction& tf, int index) {
    if (index < 0 || size_t(index) >= tf.gradientOpacity.size()) return false;
    tf.gradientOpacity.erase(tf.gradientOpacity.begin() + index);
    return true;
}

bool drawGradientOpacityCurve(renderer::TransferFunction& tf, GradientCurveEdit& edit,
                              const GradientCurveView& view) {
    const bool open = ImGui::CollapsingHeader("Gradient opacity",
                                              tf.gradientOpacity.empty() ? 0 : ImGuiTreeNodeFlags_DefaultOpen);
    // On the Undo row a narrow panel (1280 px windows) shows only the start of the label.
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Gradient opacity: a factor on each voxel's opacity by its gradient magnitude "
                          "(keep surfaces, fade insides); click to %s", open ? "close" : "open");
    if (!open) return false;
    const double maxMagnitude = view.maxMagnitude;
    if (!(maxMagnitude > 0.0)) {
        ImGui::TextDisabled(tf.gradientOpacity.empty()
                                ? "Waits for the volume's gradients"
                                : "Set; applies once the volume's gradients are computed");
        return false;
    }
    if (edit.selected >= int(tf.gradientOpacity.size())) edit.selected = -1;
    bool changed = false;

    // 1. The canvas: one button takes left presses (pick or add, then drag) and right clicks (remove).
    const auto [canvas, mouse, moved] = canvasInput("##gradient_canvas", ImGui::GetFontSize() * 5.0f);
    if (ImGui::IsItemActivated() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        int picked = pickGradientPoint(tf, canvas, mouse, maxMagnitude, kPickRadiusPx);
        if (picked < 0) {
            double magnitude = 0, factor = 0;
            canvasToGradient(canvas, mouse, maxMagnitude, magnitude, factor);
            picked = insertGradientPoint(tf, magnitude, factor, maxMagnitude);
            changed = true;
        }
        const auto& p = tf.gradientOpacity[size_t(picked)];
        const CanvasPoint at = gradientToCanvas(canvas, p.magnitude, p.opacity, maxMagnitude);
        edit.selected = picked, edit.grabDx = at.x - mouse.x, edit.grabDy = at.y - mouse.y;
    } else if (ImGui::IsItemActive() && ImGui::IsMouseDown(ImGuiMouseButton_Left) && edit.selected >= 0 &&
               moved) {
        double magnitude = 0, factor = 0;
        canvasToGradient(canvas, {mouse.x + edit.grabDx, mouse.y + edit.grabDy}, maxMagnitude, magnitude,
                         factor);
        const renderer::GradientOpacityPoint before = tf.gradientOpacity[size_t(edit.selected)];
        moveGradientPoint(tf, edit.selected, magnitude, factor);
        changed = changed || tf.gradientOpacity[size_t(edit.selected)] != before;
    }
    if (ImGui::IsItemClicked(ImGuiMouseButton_Right) &&
        removeGradientPoint(tf, pickGradientPoint(tf, canvas, mouse, maxMagnitude, kPickRadiusPx))) {
        edit.selected = -1;
        changed = true;
    }
    if (ImGui::IsItemHovered()) {
        const int over = pickGradientPoint(tf, canvas, mouse, maxMagnitude, kPickRadiusPx);
        double magnitude = 0, factor = 0;
        canvasToGradient(canvas, mouse, maxMagnitude, magnitude, factor);
        if (over >= 0) magnitude = tf.gradientOpacity[size_t(over)].magnitude;
        ImGui::SetTooltip("|gradient| %.4g (data units per world unit): opacity x %.3g\n%s", magnitude,
                          renderer::evaluateGradientOpacity(tf, magnitude),
                          over >= 0 ? "drag to move, right-click to remove" : "click to add a point here");
    }

    // 2. Drawn: the histogram of the voxels' magnitude bytes (log counts; the axis is the byte's), the
    //    curve (flat at 1 without points) and its points.
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(ImVec2(canvas.x, canvas.y), ImVec2(canvas.right(), canvas.bottom()),
                        ImGui::GetColorU32(ImGuiCol_FrameBg));
    if (view.histogram && view.histogram->size() == size_t(renderer::kGradientBins)) {
        double peak = 0.0;
        for (uint64_t c : *view.histogram)
            peak = std::max(peak, std::log1p(double(c)));
        for (int b = 0; b < renderer::kGradientBins && peak > 0.0; ++b) {
            const float x0 = canvas.x + canvas.w * float(b) / renderer::kGradientBins;
            const float x1 =
                std::max(canvas.x + canvas.w * float(b + 1) / renderer::kGradientBins, x0 + 1.0f);
            const float top =
                canvas.bottom() - float(std::log1p(double((*view.histogram)[size_t(b)])) / peak) * canvas.h;
            draw->AddRectFilled(ImVec2(x0, top), ImVec2(x1, canvas.bottom()), IM_COL32(120, 125, 140, 70));
        }
    }
    std::vector<ImVec2> line;
    for (float x = 0.0f; x <= canvas.w; x += 2.0f) {
        const double t = double(x) / canvas.w, magnitude = maxMagnitude * t * t;
        line.push_back(ImVec2(canvas.x + x,
                              gradientToCanvas(canvas, magnitude,
                                               renderer::evaluateGradientOpacity(tf, magnitude), maxMagnitude)
                                  .y));
    }
    draw->AddPolyline(line.data(), int(line.size()), IM_COL32(235, 235, 235, 255), 0, 1.5f);
    for (size_t i = 0; i < tf.gradientOpacity.size(); ++i) {
        const auto& p = tf.gradientOpacity[i];
        const CanvasPoint c = gradientToCanvas(canvas, p.magnitude, p.opacity, maxMagnitude);
        const bool selected = int(i) == edit.selected;
        draw->AddCircleFilled(ImVec2(c.x, c.y), selected ? kPointRadiusPx + 1.5f : kPointRadiusPx,
                              IM_COL32(255, 255, 255, 255));
        if (selected)
            draw->AddCircle(ImVec2(c.x, c.y), kPointRadiusPx + 3.0f, ImGui::GetColorU32(ImGuiCol_CheckMark),
                            0, 2.0f);
    }
    ImGui::TextDisabled("0   (sqrt axis)   %.4g per world unit", maxMagnitude);

    // 3. The whole function: the classic ramp, or none.
    if (ImGui::Button("Fade insides")) {
        tf.gradientOpacity = {{0.0, 0.0}, {kFadeInsidesShare * maxMagnitude, 1.0}};
        edit.selected = -1;
        changed = true;
    }
    hint("Opacity x 0 where the value does not change (the insides of uniform regions), rising to x 1 at a\n"
         "tenth of the largest gradient: surfaces stay, insides fade");
    ImGui::SameLine();
    ImGui::BeginDisabled(tf.gradientOpacity.empty());
    if (ImGui::Button("None")) {
        tf.gradientOpacity.clear();
        edit.selected = -1;
        changed = true;
    }
    ImGui::EndDisabled();
    hint("No gradient opacity: a factor of 1 at every gradient");
    return changed;
}

} // namespace ui
