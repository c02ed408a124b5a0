// The rules behind the Transfer function panel's curve, as pure functions (tests drive them with no
// ImGui): where an opacity point or colour stop sits, which one the mouse picks, and the edits. The canvas
// spans the window (a fraction 0..1 across), the TF's values are data units, opacity 0..1 upwards; the
// points stay sorted.
#pragma once
#include "renderer/model/transfer_function.h"
#include "renderer/model/volume.h"
#include "ui/dock_layout.h"

#include <vector>

namespace ui {

struct CanvasPoint {
    float x = 0, y = 0;   // display pixels, y down
};

// The curve's vertical axis: linear in opacity (the TF's extinction per voxel length at density 1), or
// logarithmic over kLogOpacityDecades decades below 1, which opens up the faint range where a CT's air and
// skin live; opacities below its floor sit on the baseline.
enum class OpacityAxis { Linear, Log };
constexpr double kLogOpacityDecades = 3.0;
// Within this many pixels of the baseline (the top), a drag or click gives exactly 0 (1).
constexpr float kOpacitySnapPx = 3.0f;

// (value, opacity) -> canvas pixels and back; canvasToTf clamps to the domain and snaps to 0 and 1.
CanvasPoint tfToCanvas(const Rect& canvas, double value, double opacity, OpacityAxis axis = OpacityAxis::Linear);
void canvasToTf(const Rect& canvas, CanvasPoint p, double& value, double& opacity,
                OpacityAxis axis = OpacityAxis::Linear);

// The opacity point drawn nearest to `mouse`, if within radiusPx; -1 when none is. Values are data units,
// shown over `window` (the canvas's left and right edges).
int pickOpacityPoint(const renderer::TransferFunction& tf, renderer::ValueRange window, const Rect& canvas,
                     CanvasPoint mouse, float radiusPx, OpacityAxis axis = OpacityAxis::Linear);
// The colour stop nearest to `mouse` across (stops are drawn as markers spanning `bar`'s height), if
// within radiusPx of it across and inside the bar's rows; -1 when none is.
int pickColourStop(const renderer::TransferFunction& tf, renderer::ValueRange window, const Rect& bar,
                   CanvasPoint mouse, float radiusPx);

// Adds an opacity point at `value` with `opacity`; the colours do not change. Returns its index.
int insertOpacityPoint(renderer::TransferFunction& tf, double value, double opacity);
// Adds a colour stop at `value` with the colour the TF already has there; opacity does not change.
int insertColourStop(renderer::TransferFunction& tf, double value);

// Moves a point: its value stays between its neighbours' (the order never changes under a drag), opacity
// within 0..1. Non-finite inputs leave that coordinate as it was; an index out of range does nothing.
// Each touches only its own function: a colour stop's move never changes opacity, and the reverse.
void moveOpacityPoint(renderer::TransferFunction& tf, int index, double value, double opacity);
void moveColourStop(renderer::TransferFunction& tf, int index, double value);

// Removes a point unless only two are left in its function (a start and an end); returns whether it did.
bool removeOpacityPoint(renderer::TransferFunction& tf, int index);
bool removeColourStop(renderer::TransferFunction& tf, int index);

// The ranges the panel's Rescale maps the TF's extent onto (renderer::rescaled).
enum class RescaleTarget { DataRange, Window, Percentile, Visible };
const char* rescaleTargetName(RescaleTarget target);   // "data", "window", "1-99 %", "visible"

// Undo and redo of TF edits, a step per gesture (a drag, a typed field, a preset, a file).
constexpr size_t kTfHistorySteps = 100;
struct TfHistory {
    std::vector<renderer::TransferFunction> undo, redo;
    // Before an edit: `before` becomes the step undo returns to; redo is forgotten. Keeps the newest
    // kTfHistorySteps.
    void record(const renderer::TransferFunction& before);
    // Swap `tf` for the previous (next) state; false when there is none.
    bool undoInto(renderer::TransferFunction& tf);
    bool redoInto(renderer::TransferFunction& tf);
};

// A fraction of `window` (the canvas's width) <-> data units. fromDataUnits clamps to 0..1 (where the
// mouse can be); windowFraction does not (where a point outside the window would be drawn).
double toDataUnits(double fraction, renderer::ValueRange window);
double fromDataUnits(double data, renderer::ValueRange window);
double windowFraction(double data, renderer::ValueRange window);

} // namespace ui
