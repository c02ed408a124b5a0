// The footprint inspector: Settings > Inspect > Footprint inspector on, the voxel under the pointer shows
// its footprint in an inset at the viewport's corner, magnified on the image's pixel grid: the ellipses
// of the projected reconstruction kernel (red), the low-pass filter (green) and their sum, EWA (blue), at
// the cutoff, with their radii, |J|, the filter its patch takes and the thresholds it was measured
// against. Colours as the filter-mode heatmap's.
#pragma once
#include "renderer/oracle/footprint_inspection.h"

#include <array>

namespace ui {

// Where the inset draws, in screen units: a square `sidePx` wide whose centre is the footprint's centre,
// at `magnification` screen units per image pixel (whole when at least 1, so that the pixel grid shows
// as whole squares), chosen so that EWA's cutoff ellipse (the largest) spans at most 90 % of the side.
struct FootprintInset {
    float sidePx = 0.0f;
    double magnification = 1.0;
    std::array<renderer::Ellipse, 3> ellipses; // reconstruction, low-pass, EWA; semi-axes in screen units
};
FootprintInset footprintInset(const renderer::FootprintInspection& f, float sidePx);

// Draws the inset with its figures (and the voxel's `value` in data units) into the current window, its
// top-right corner at (topRightX, topRightY).
void drawFootprintInspector(const renderer::FootprintInspection& f, float value, float topRightX, float topRightY);

} // namespace ui
