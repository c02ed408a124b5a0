// The Transfer function panel's 2D section: the 2D transfer function's widgets (renderer::Widget2D) drawn
// over the histogram of (value, gradient magnitude), added, moved, resized and removed with the mouse.
// The edit rules are pure functions (tests drive them with no ImGui); drawTf2dSection maps ImGui input
// onto them.
#pragma once
#include "renderer/model/transfer_function.h"
#include "renderer/model/volume.h"
#include "ui/dock_layout.h"
#include "ui/tf_editor.h"

#include <cstdint>
#include <vector>

namespace ui {

// The canvas's axes: the value across over `window` (data units, as the opacity curve's), the gradient
// magnitude upwards as sqrt(|g| / maxMagnitude) (the packed magnitude byte's axis, as the gradient
// opacity curve's), data units per world unit.
struct Tf2dAxes {
    renderer::ValueRange window;
    double maxMagnitude = 0.0;
};
CanvasPoint tf2dToCanvas(const Rect& canvas, const Tf2dAxes& axes, double value, double magnitude);
// Back: the value unclamped (a widget may reach past the window), the magnitude within 0 .. maxMagnitude.
void canvasToTf2d(const Rect& canvas, const Tf2dAxes& axes, CanvasPoint p, double& value, double& magnitude);

// What of a widget the mouse holds. A rectangle: its body (moves it) or a corner (resizes it; the
// opposite corner stays). A triangle: its body or apex (moves it along the value axis: its apex stays at
// magnitude 0), a top corner (half-width and top) or the middle of its top edge (top only).
enum class WidgetHandle { None, Body, LowLow, HighLow, LowHigh, HighHigh, Apex, TopLeft, TopRight, TopEdge };
struct WidgetPick {
    int index = -1;
    WidgetHandle handle = WidgetHandle::None;
};
// The handles of a widget where they are drawn.
struct HandleAt {
    WidgetHandle handle;
    CanvasPoint at;
};
std::vector<HandleAt> widgetHandles(const renderer::Widget2D& w, const Rect& canvas, const Tf2dAxes& axes);
// The handle within radiusPx of `mouse` (the selected widget's first, then the topmost: the last drawn),
// else the topmost widget whose shape holds the mouse (Body); {-1, None} when none.
WidgetPick pickWidget(const renderer::TransferFunction& tf, const Rect& canvas, const Tf2dAxes& axes,
                      CanvasPoint mouse, float radiusPx, int selected = -1);
// `atPress` with `handle` dragged from canvas point `press` to `now` (so a drag never drifts: each frame
// starts from the widget as it was at the press). Lows stay below highs, a triangle keeps a width and a
// top above 0, magnitudes stay >= 0.
renderer::Widget2D draggedWidget(const renderer::Widget2D& atPress, WidgetHandle handle, const Rect& canvas,
                                 const Tf2dAxes& axes, CanvasPoint press, CanvasPoint now);
// A new widget in the middle of the axes (the rectangle over the middle fifth of the values and a band
// of magnitudes, the triangle with its apex at the middle value, a tenth of the window wide each side
// and its top halfway up), each in its own colour from a short palette. Returns its index.
int addRectangle(renderer::TransferFunction& tf, const Tf2dAxes& axes);
int addTriangle(renderer::TransferFunction& tf, const Tf2dAxes& axes);
bool removeWidget(renderer::TransferFunction& tf, int index);

// The section's state in EditorState: the selected widget, and the drag under way.
struct Tf2dEdit {
    int selected = -1;
    WidgetHandle handle = WidgetHandle::None;   // held since the press; None between drags
    renderer::Widget2D atPress;
    CanvasPoint press;
};
struct Tf2dView {
    Tf2dAxes axes;                                // maxMagnitude 0: the gradients are not computed yet
    const std::vector<uint32_t>* histogram = nullptr;   // voxels per 2D TF cell (valueGradientHistogram), or null
    renderer::ValueRange histogramWindow{};       // the values its cells span (the scene's window)
};
// The collapsible "2D transfer function" section: the canvas (drag a widget or its handles, right-click
// one to remove it), "Add rectangle", "Add triangle", and the selected widget's colour and opacity.
// Returns whether tf changed.
bool drawTf2dSection(renderer::TransferFunction& tf, Tf2dEdit& edit, const Tf2dView& view);

} // namespace ui
