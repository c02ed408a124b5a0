// The filter-mode heatmap's legend, drawn in the viewport over the image: a colour per filter regime and
// the adaptive classifier's thresholds for the view shown, in pixels and in depths. The figures come from
// renderer/math/classifier.h (adaptiveThresholds, filterDepths), the code the classifier itself runs.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_settings.h"

#include <array>
#include <string>

namespace ui {

struct HeatmapLegend {
    double reconstructionAbovePx = 0.0; // a kernel's sigma on screen above this: reconstruction only
    double lowPassBelowPx = 0.0;        // below this: low-pass only; EWA between
    double reconstructionNearer = 0.0;  // the same thresholds as depths from the eye, in bounding radii
    double lowPassFarther = 0.0;        // (orthographic: 0 or infinity, one filter everywhere)
    bool orthographic = false;
    double fovYDeg = 0.0;
    // One line per regime, nearest first: reconstruction, EWA, low-pass (indices into kModeName: 0, 2, 1).
    std::array<std::string, 3> rows;
    std::string footer; // what the depths are measured in, and the view they hold for
};

// The legend of `plane` (the view shown) for a volume of voxel `spacing` and bounding `radius`.
HeatmapLegend heatmapLegend(glm::dvec3 spacing, double radius, const renderer::ImagePlane& plane,
                            const renderer::SplatSettings& settings, double fovYDeg);

// Draws the legend in a dark box at the bottom-left corner of the rectangle [min, max] (screen pixels).
void drawHeatmapLegend(const HeatmapLegend& legend, float minX, float minY, float maxX, float maxY);

} // namespace ui
