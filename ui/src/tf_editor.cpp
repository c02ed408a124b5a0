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

int pickOpacityPoint(const renderer::TransferFunction& tf, renderer::ValueRange window, const Rect& canvas,
                     CanvasPoint mouse, float radiusPx, OpacityAxis axis) {
    int best = -1;
    float bestD2 = radiusPx * radiusPx;
    for (size_t i = 0; i < tf.opacities.size(); ++i) {
        const auto& p = tf.opacities[i];
        const CanvasPoint c = tfToCanvas(canvas, windowFraction(p.value, window), p.opacity, axis);
        const float dx = c.x - mouse.x, dy = c.y - mouse.y, d2 = dx * dx + dy * dy;
        if (d2 <= bestD2) best = int(i), bestD2 = d2;   // ties: the later point, drawn on top
    }
    return best;
}

int pickColourStop(const renderer::TransferFunction& tf, renderer::ValueRange window, const Rect& bar,
                   CanvasPoint mouse, float radiusPx) {
    if (mouse.y < bar.y || mouse.y > bar.bottom()) return -1;
    int best = -1;
    float bestDx = radiusPx;
    for (size_t i = 0; i < tf.colours.size(); ++i) {
        const float x = tfToCanvas(bar, windowFraction(tf.colours[i].value, window), 0.0).x;
        const float dx = std::abs(x - mouse.x);
        if (dx <= bestDx) best = int(i), bestDx = dx;   // ties: the later stop, drawn on top
    }
    return best;
}

namespace {

// Where `value` goes in a sorted list: after the points at the same value.
template <class Point>
typename std::vector<Point>::iterator insertionPoint(std::vector<Point>& pts, double value) {
    return std::upper_bound(pts.begin(), pts.end(), value, [](double v, const Point& p) { return v < p.value; });
}

// The value of point `index` moved to `value`, kept between its neighbours.
template <class Point>
void moveBetweenNeighbours(std::vector<Point>& pts, size_t index, double value) {
    if (!std::isfinite(value)) return;
    const double lo = index > 0 ? pts[index - 1].value : -INFINITY;
    const double hi = index + 1 < pts.size() ? pts[index + 1].value : INFINITY;
    pts[index].value = std::clamp(value, lo, hi);
}

} // namespace

int insertOpacityPoint(renderer::TransferFunction& tf, double value, double opacity) {
    auto at = insertionPoint(tf.opacities, value);
    at = tf.opacities.insert(at, {value, std::clamp(opacity, 0.0, 1.0)});
    return int(at - tf.opacities.begin());
}

int insertColourStop(renderer::TransferFunction& tf, double value) {
    const glm::dvec3 here(renderer::evaluate(tf, value));
    auto at = insertionPoint(tf.colours, value);
    at = tf.colours.insert(at, {value, here});
    return int(at - tf.colours.begin());
}

void moveOpacityPoint(renderer::TransferFunction& tf, int index, double value, double opacity) {
    if (index < 0 || size_t(index) >= tf.opacities.size()) return;
    moveBetweenNeighbours(tf.opacities, size_t(index), value);
    if (std::isfinite(opacity)) tf.opacities[size_t(index)].opacity = std::clamp(opacity, 0.0, 1.0);
}

void moveColourStop(renderer::TransferFunction& tf, int index, double value) {
    if (index < 0 || size_t(index) >= tf.colours.size()) return;
    moveBetweenNeighbours(tf.colours, size_t(index), value);
}

bool removeOpacityPoint(renderer::TransferFunction& tf, int index) {
    if (tf.opacities.size() <= 2 || index < 0 || size_t(index) >= tf.opacities.size()) return false;
    tf.opacities.erase(tf.opacities.begin() + index);
    return true;
}

bool removeColourStop(renderer::TransferFunction& tf, int index) {
    if (tf.colours.size() <= 2 || index < 0 || size_t(index) >= tf.colours.size()) return false;
    tf.colours.erase(tf.colours.begin() + index);
    return true;
}

const char* rescaleTargetName(RescaleTarget target) {
    switch (target) {
    case RescaleTarget::DataRange: return "data";
    case RescaleTarget::Window: return "window";
    case RescaleTarget::Percentile: return "1-99 %";
    case RescaleTarget::Visible: return "visible";
    }
    return "?";
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

double toDataUnits(double fraction, renderer::ValueRange window) {
    return double(window.lo) + fraction * (double(window.hi) - double(window.lo));
}

double fromDataUnits(double data, renderer::ValueRange window) {
    const double span = double(window.hi) - double(window.lo);
    return span > 0 ? std::clamp((data - window.lo) / span, 0.0, 1.0) : 0.0;
}

double windowFraction(double data, renderer::ValueRange window) {
    const double span = double(window.hi) - double(window.lo);
    return span > 0 ? (data - window.lo) / span : 0.0;
}

} // namespace ui
