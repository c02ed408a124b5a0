// The Transfer function panel's curve rules (tf_editor.h).
#include "ui/tf_editor.h"

#include <algorithm>
#include <cmath>

namespace ui {

namespace {

// The height of `opacity` on the axis, 0 (baseline) .. 1 (top).
double axisFraction(double opacity, OpacityAxis axis) {
    if (axis == OpacityAxis::Linear) return opacity;
    const double floor = std::pow(10.0, -kLogOpacityDecades);
    return opacity <= floor ? 0.0 : std::min(1.0, 1.0 + std::log10(opacity) / kLogOpacityDecades);
}

double opacityAt(double fraction, OpacityAxis axis) {
    if (axis == OpacityAxis::Linear) return fraction;
    return fraction <= 0.0 ? 0.0 : std::pow(10.0, (fraction - 1.0) * kLogOpacityDecades);
}

} // namespace

CanvasPoint tfToCanvas(const Rect& canvas, double value, double opacity, OpacityAxis axis) {
    return {canvas.x + float(value) * canvas.w, canvas.bottom() - float(axisFraction(opacity, axis)) * canvas.h};
}

void canvasToTf(const Rect& canvas, CanvasPoint p, double& value, double& opacity, OpacityAxis axis) {
    value = canvas.w > 0 ? std::clamp(double(p.x - canvas.x) / canvas.w, 0.0, 1.0) : 0.0;
    if (!(canvas.h > 0) || canvas.bottom() - p.y <= kOpacitySnapPx) {
        opacity = 0.0;
    } else if (p.y - canvas.y <= kOpacitySnapPx) {
        opacity = 1.0;
    } else {
        opacity = std::clamp(opacityAt(double(canvas.bottom() - p.y) / canvas.h, axis), 0.0, 1.0);
    }
}

int pickControlPoint(const renderer::TransferFunction& tf, const Rect& canvas, CanvasPoint mouse, float radiusPx,
                     OpacityAxis axis) {
    int best = -1;
    float bestD2 = radiusPx * radiusPx;
    for (size_t i = 0; i < tf.points.size(); ++i) {
        const CanvasPoint c = tfToCanvas(canvas, tf.points[i].value, tf.points[i].opacity, axis);
        const float dx = c.x - mouse.x, dy = c.y - mouse.y, d2 = dx * dx + dy * dy;
        if (d2 <= bestD2) best = int(i), bestD2 = d2;   // ties: the later point, drawn on top
    }
    return best;
}

int insertControlPoint(renderer::TransferFunction& tf, double value, double opacity) {
    value = std::clamp(value, 0.0, 1.0);
    const glm::dvec4 here = renderer::evaluate(tf, value);
    auto at = std::upper_bound(tf.points.begin(), tf.points.end(), value,
                               [](double v, const renderer::ControlPoint& p) { return v < p.value; });
    at = tf.points.insert(at, {value, glm::dvec3(here), std::clamp(opacity, 0.0, 1.0)});
    return int(at - tf.points.begin());
}

void moveControlPoint(renderer::TransferFunction& tf, int index, double value, double opacity) {
    if (index < 0 || size_t(index) >= tf.points.size()) return;
    renderer::ControlPoint& p = tf.points[size_t(index)];
    const double lo = index > 0 ? tf.points[size_t(index) - 1].value : 0.0;
    const double hi = size_t(index) + 1 < tf.points.size() ? tf.points[size_t(index) + 1].value : 1.0;
    if (std::isfinite(value)) p.value = std::clamp(value, lo, hi);
    if (std::isfinite(opacity)) p.opacity = std::clamp(opacity, 0.0, 1.0);
}

bool removeControlPoint(renderer::TransferFunction& tf, int index) {
    if (tf.points.size() <= 2 || index < 0 || size_t(index) >= tf.points.size()) return false;
    tf.points.erase(tf.points.begin() + index);
    return true;
}

void TfHistory::record(const renderer::TransferFunction& before) {
    undo.push_back(before);
    if (undo.size() > kTfHistorySteps) undo.erase(undo.begin());
    redo.clear();
}

bool TfHistory::undoInto(renderer::TransferFunction& tf) {
    if (undo.empty()) return false;
    redo.push_back(std::move(tf));
    tf = std::move(undo.back());
    undo.pop_back();
    return true;
}

bool TfHistory::redoInto(renderer::TransferFunction& tf) {
    if (redo.empty()) return false;
    undo.push_back(std::move(tf));
    tf = std::move(redo.back());
    redo.pop_back();
    return true;
}

double toDataUnits(double value, renderer::ValueRange window) {
    return double(window.lo) + value * (double(window.hi) - double(window.lo));
}

double fromDataUnits(double data, renderer::ValueRange window) {
    const double span = double(window.hi) - double(window.lo);
    return span > 0 ? std::clamp((data - window.lo) / span, 0.0, 1.0) : 0.0;
}

} // namespace ui
