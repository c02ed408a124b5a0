// The split view's plain parts: two or four panes at one camera, each with its own filter and compositing,
// and an optional difference pane, |A - B| or |A - ground truth|, with its colour scale and error. The
// layout, each pane's settings and the difference image are pure functions (unit-tested); drawing them is
// split_viewport.cpp's job.
#pragma once
#include "renderer/io/image.h"
#include "renderer/math/ewa.h"
#include "renderer/model/splat_settings.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ui {

// What one pane overrides of the view's settings; everything else (kernel, density, shading...) is shared.
struct SplitPane {
    renderer::FilterMode filter = renderer::FilterMode::Ewa;
    renderer::Compositing compositing = renderer::Compositing::SheetFrontToBack;
};

// What the difference pane shows: nothing (no pane), |A - B|, or |A - ground truth| (renderer/oracle/
// ground_truth.h: the reference Measure and `splatlab report` compare with).
enum class SplitDifference { Off, AgainstB, AgainstTruth };
const char* splitDifferenceName(SplitDifference d);               // "off", "b", "truth"
SplitDifference splitDifferenceFromName(const std::string& name); // RenderError naming the known ones

// Settings > View > Split view (and --split A,B[,C,D]): panes at one camera, navigation linked by it.
struct SplitView {
    bool enabled = false;
    int imagePanes = 2; // 2 (side by side) or 4 (2 x 2)
    std::array<SplitPane, 4> panes{SplitPane{renderer::FilterMode::Reconstruction}, SplitPane{},
                                   SplitPane{renderer::FilterMode::LowPass},
                                   SplitPane{renderer::FilterMode::Adaptive}};
    SplitDifference difference = SplitDifference::Off;
    // The image panes shown (1: no split), and with the difference pane.
    int shownImagePanes() const { return enabled ? (imagePanes == 4 ? 4 : 2) : 1; }
    int paneCount() const { return enabled ? shownImagePanes() + (difference != SplitDifference::Off) : 1; }
};

// A pane's rectangle in the viewport, in framebuffer pixels (x right, y down).
struct PaneRect {
    int x = 0, y = 0, width = 0, height = 0;
};

// Where the panes go over a viewport of `width` x `height`: every pane is the same size (they share one
// image plane), each at least 1 x 1. Two image panes side by side, the difference (if any) a third
// column; four in a 2 x 2 grid (A B over C D), the difference a third column centred beside the grid, so
// that the four keep their places whether it is on or not. Leftover pixels stay empty at the right and
// bottom.
struct SplitLayout {
    std::vector<PaneRect> panes;        // the image panes, A first (row by row)
    std::optional<PaneRect> difference; // the difference pane, when on
};
SplitLayout splitLayout(int width, int height, int imagePanes, bool difference);
// The layout's rectangles in one list: the image panes, then the difference pane.
std::vector<PaneRect> splitPaneRects(int width, int height, int imagePanes, bool difference);

// The view's settings with the pane's filter and compositing. A pane that composites every sample cannot
// use tiles (they need sheets or X-ray), so a primitive forced to Tiles falls back to Auto there.
renderer::SplatSettings paneSettings(renderer::SplatSettings view, const SplitPane& pane);

// "reconstruction, sheets front to back": what a pane's label says.
std::string paneLabel(const SplitPane& pane);

// `image` (a coarse ground truth) resampled to `width` x `height`, bilinear between pixel centres (edges
// clamped): how a quarter-resolution truth is shown over the pane until the full one is in.
renderer::Image upsampleBilinear(const renderer::Image& image, int width, int height);

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
