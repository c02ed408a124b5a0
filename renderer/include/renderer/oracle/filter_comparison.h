// Each filter's cost beside its error in one view (the editor's Filters panel): the frame time of the
// whole view, and the error against the ground truth over a crop of it, so that the ground truth
// (seconds to minutes on the CPU) covers a few thousand pixels and not the whole image.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/io/image.h"
#include "renderer/math/metrics.h"
#include "renderer/gl/splat_renderer.h"

namespace renderer {

struct FilterMeasurement {
    FilterMode filter = FilterMode::Ewa;
    double frameMs = 0.0;   // median wall time of the timed frames of the whole view (render + glFinish)
    double rmse = 0.0;      // the crop against its ground truth (metrics.h)
    double psnrDb = 0.0;
};

// The centre square of `view`, `side` pixels a side or the whole of a smaller view, as an image
// plane of its own (cropPlane: the same pixels as in the view).
ImagePlane centreCrop(const ImagePlane& view, int side);
// The side of the crop the editor's Measure and renderer_bench take errors over: a ground truth of
// seconds to a minute on two cores, where the whole view's would take many minutes.
constexpr int kComparisonCropPx = 96;

// `crop` rendered once with `settings`, against `cropTruth`, its ground truth for these settings.
ImageError cropError(SplatRenderer& gl, const ImagePlane& crop, const Image& cropTruth, const SplatSettings& settings);

// Renders `view` `frames` times with `settings` under `filter` (one untimed frame first), then
// `crop` once, and compares it with `cropTruth`, the ground truth of `crop` for these settings.
FilterMeasurement measureFilter(SplatRenderer& gl, const ImagePlane& view, const ImagePlane& crop,
                                const Image& cropTruth, SplatSettings settings, FilterMode filter, int frames);

} // namespace renderer
