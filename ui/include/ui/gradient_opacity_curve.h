// The Transfer function panel's gradient opacity curve: |gradient| -> a factor on opacity (ParaView's and
// Slicer's gradient opacity), in a collapsible section under the opacity curve. The edit rules are pure
// functions (tests drive them with no ImGui); drawGradientOpacityCurve maps ImGui input onto them.
#pragma once
#include "renderer/model/transfer_function.h"
#include "ui/dock_layout.h"
#include "ui/tf_editor.h"

#include <cstdint>
#include <vector>

namespace ui {

// The canvas: sqrt(|g| / maxMagnitude) across, as the packed magnitude byte (shading.h), so the weak
// gradients of insides and noise get room; the factor 0..1 upwards, snapping to 0 and 1 at the edges
// (kOpacitySnapPx). Magnitudes are data units per world unit; points past maxMagnitude sit on the right edge.
CanvasPoint gradientToCanvas(const Rect& canvas, double magnitude, double factor, double maxMagnitude);
void canvasToGradient(const Rect& canvas, CanvasPoint p, double maxMagnitude, double& magnitude,
                      double& factor);
// The gradient point drawn nearest to `mouse`, if within radiusPx; -1 when none is.
int pickGradientPoint(const renderer::TransferFunction& tf, const Rect& canvas, CanvasPoint mouse,
                      double maxMagnitude, float radiusPx);
// Adds a point (kept sorted) and returns its index. On a TF without gradient opacity (a factor of 1
// everywhere) it first adds the ends at 0 and maxMagnitude with factor 1, so only the new point changes it.
int insertGradientPoint(renderer::TransferFunction& tf, double magnitude, double factor, double maxMagnitude);
// Moves a point between its neighbours, factor within 0..1; non-finite inputs keep that coordinate.
void moveGradientPoint(renderer::TransferFunction& tf, int index, double magnitude, double factor);
// Removes a point; removing the last leaves no gradient opacity. Returns whether it removed one.
bool removeGradientPoint(renderer::TransferFunction& tf, int index);

// The section's state in EditorState (the selected point, the drag's grab offset).
struct GradientCurveEdit {
    int selected = -1;
    float grabDx = 0, grabDy = 0;
};
struct GradientCurveView {
    double maxMagnitude = 0.0;                        // the volume's largest |gradient|; 0: not computed yet
    const std::vector<uint64_t>* histogram = nullptr; // voxels per magnitude byte (kGradientBins), or null
};
// The collapsible "Gradient opacity" section: the curve over the histogram of gradient magnitudes (drag a
// point, click empty space to add one, right-click one to remove it), "Fade insides" (a ramp from 0 at no
// gradient to 1 at a tenth of the largest) and "None". Returns whether tf changed.
bool drawGradientOpacityCurve(renderer::TransferFunction& tf, GradientCurveEdit& edit,
                              const GradientCurveView& view);

} // namespace ui
