// The split view's plain parts: two panes at one camera, each with its own filter and compositing, and an
// optional difference pane |A - B| with its colour scale and error. The layout, each pane's settings and
// the difference image are pure functions (unit-tested); drawing them is split_viewport.cpp's job.
#pragma once
#include "renderer/io/image.h"
#include "renderer/math/ewa.h"
#include "renderer/model/splat_settings.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ui {

// What one pane overrides of the view's settings; everything else (kernel, density, shading...) is shared.
struct SplitPane {
    renderer::FilterMode filter = renderer::FilterMode::Ewa;
    renderer::Compositing compositing = renderer::Compositing::SheetFrontToBack;
};

// Settings > View > Split view (and --split A,B): panes side by side, navigation linked by the one camera.
struct SplitView {
    bool enabled = false;
    std::array<SplitPane, 2> panes{SplitPane{renderer::FilterMode::Reconstruction}, SplitPane{}};
    bool difference = false; // a third pane: |A - B| with its colour scale, RMSE and PSNR
    int paneCount() const { return enabled ? (difference ? 3 : 2) : 1; }
};

// A pane's rectangle in the viewport, in framebuffer pixels (x right, y down).
struct PaneRect {
    int x = 0, y = 0, width = 0, height = 0;
};

// `count` equal panes side by side over a viewport of `width` x `height`: every pane is the same size (they
// share one image plane), floor(width / count) wide; the leftover columns (fewer than `count`) stay empty
// at the right. Each pane is at least 1 x 1.
std::vector<PaneRect> splitPaneRects(int width, int height, int count);

// The view's settings with the pane's filter and compositing. A pane that composites every sample cannot
// use tiles (they need sheets or X-ray), so a primitive forced to Tiles falls back to Auto there.
renderer::SplatSettings paneSettings(renderer::SplatSettings view, const SplitPane& pane);

// "reconstruction, sheets front to back": what a pane's label says.
std::string paneLabel(const SplitPane& pane);

// |A - B| as the difference pane shows it. Each pixel's error is the RMS of its four premultiplied RGBA
// channels' differences, so the mean of its square over the image is the square of renderer::compareImages'
// RMSE (EWA_NOTES' metric, which `rmse` and `psnrDb` are).
struct DifferencePane {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba; // each pixel's error on the colour scale, opaque, row 0 at the top
    double rmse = 0.0;         // renderer::compareImages(a, b)
    double psnrDb = 0.0;       // its PSNR (+inf for identical images)
    double scaleMax = 0.0;     // the error at the top of the colour scale: a 1-2-5 step over the 99th
                               // percentile of the pixels that differ (larger ones take its top colour)
    double maxError = 0.0;     // the largest pixel error
};
// Throws RenderError (compareImages) when the sizes differ.
DifferencePane differencePane(const renderer::Image& a, const renderer::Image& b);

// The colour scale, 0 at dark blue-black through purple and orange to pale yellow at 1 (inferno-like, so
// it reads in grey too); `t` is clamped to [0, 1]. RGB, 8 bits each.
std::array<uint8_t, 3> differenceColour(double t);
// The smallest of 1, 2, 5 x 10^k at or above `x` (x > 0); 1e-6 for anything smaller or not a number.
double niceScaleMax(double x);

} // namespace ui
