// Speed against error as a chart (the Filters panel's Measure; `splatlab report` draws the same layout
// as SVG): frame time across, median with a p10-p90 whisker, PSNR up, the Pareto front joined, the
// current setting ringed. The layout is plain arithmetic the tests check; drawing it is ImGui's.
#pragma once
#include "renderer/oracle/filter_comparison.h"

#include <span>
#include <string>
#include <vector>

namespace ui {

// A linear axis from lo to hi (lo < hi) with ticks at round steps (1, 2 or 5 x 10^k) inside it.
struct ChartAxis {
    double lo = 0.0, hi = 1.0;
    std::vector<double> ticks;
};

struct ChartPoint {
    double x = 0, xLo = 0, xHi = 0; // median, p10 and p90 frame time, in pixels
    double y = 0;                   // PSNR in pixels (an identical image, +inf dB, at the top edge)
    bool pareto = false;            // on the Pareto front (renderer::paretoFront)
    bool current = false;           // the filter and compositing of the settings in force (and their slabs)
};

struct SpeedErrorChart {
    double left = 0, top = 0, right = 1, bottom = 1; // the plot rectangle, pixels (y down)
    ChartAxis timeMs, psnrDb;
    std::vector<ChartPoint> points; // one per measurement, in their order
    std::vector<size_t> front; // the Pareto fronts' points, the attenuating modes', X-ray's, then the
                               // post-classified slabs', each fastest first: a line joins two neighbours
                               // that share a ground truth
    double xAt(double ms) const { return left + (ms - timeMs.lo) / (timeMs.hi - timeMs.lo) * (right - left); }
    double yAt(double db) const; // clamped to the plot: +inf dB at the top
};

// Time from 0 to past the slowest p90, PSNR from below the lowest to above the highest finite value,
// over the plot rectangle (left, top)-(right, bottom). `current`: the settings in force, or null;
// `slabsInForce`: the view shown ends in image-aligned slabs (their point is the one in force).
SpeedErrorChart layoutSpeedErrorChart(std::span<const renderer::FilterMeasurement> points,
                                      const renderer::SplatSettings* current, double left, double top,
                                      double right, double bottom, bool slabsInForce = false);

// "ewa, sheet-front-to-back", "ewa, image-aligned slabs 0.5, post-classified": what a point's label and
// tooltip call it.
std::string settingLabel(const renderer::FilterMeasurement& m);
// Marker colour by filter (RGB 0..255; adaptive grey-white) and shape by compositing: circle for
// splat-every-sample, square and diamond for the sheets, triangle for X-ray, hexagon for image-aligned slabs.
struct PointStyle {
    unsigned char r, g, b;
    enum Shape { Circle, Square, Diamond, Triangle, Hexagon } shape;
};
PointStyle pointStyle(const renderer::FilterMeasurement& m);

// The chart, `height` pixels tall across the available width, with axis labels and a hover tooltip per
// point. Returns the layout drawn (screen pixels), which the tests compare with the measurements.
SpeedErrorChart drawSpeedErrorChart(std::span<const renderer::FilterMeasurement> points,
                                    const renderer::SplatSettings& current, float height, bool slabsInForce = false);

} // namespace ui
