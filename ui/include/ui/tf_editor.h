// The rules behind the Transfer function panel's curve, as pure functions (tests drive them with no
// ImGui): where a control point sits on the canvas, which one the mouse picks, and the edits. Values
// are the TF's normalised domain (0..1 over the window), opacity 0..1 upwards; the points stay sorted.
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

// The control point drawn nearest to `mouse`, if within radiusPx; -1 when none is.
int pickControlPoint(const renderer::TransferFunction& tf, const Rect& canvas, CanvasPoint mouse, float radiusPx,
                     OpacityAxis axis = OpacityAxis::Linear);

// Adds a point at `value` with `opacity` and the colour the TF already has there, so the colours do
// not change; returns its index.
int insertControlPoint(renderer::TransferFunction& tf, double value, double opacity);

// Moves point `index`: its value stays between its neighbours' (the order never changes under a
// drag), opacity within 0..1. Non-finite inputs leave that coordinate as it was.
void moveControlPoint(renderer::TransferFunction& tf, int index, double value, double opacity);

// Removes point `index` unless only two are left (a TF needs a start and an end); returns whether it did.
bool removeControlPoint(renderer::TransferFunction& tf, int index);

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

// Data units <-> the TF's normalised domain over `window` (what the panel shows and types).
double toDataUnits(double value, renderer::ValueRange window);
double fromDataUnits(double data, renderer::ValueRange window);

} // namespace ui
