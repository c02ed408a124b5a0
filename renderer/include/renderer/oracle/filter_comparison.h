// Each setting's cost beside its error in one view (the editor's Measure, `splatlab report`): the frame
// time of the whole view, and the error against the ground truth over a crop of it, so that the ground
// truth (seconds to minutes on the CPU) covers a few thousand pixels and not the whole image.
#pragma once
#include "renderer/gl/splat_renderer.h"
#include "renderer/io/image.h"
#include "renderer/math/camera.h"
#include "renderer/math/metrics.h"
#include "renderer/oracle/image_slabs.h"

#include <functional>
#include <vector>

namespace renderer {

struct FilterMeasurement {
    FilterMode filter = FilterMode::Ewa;
    Compositing compositing = Compositing::SplatEverySample;
    double frameMs = 0.0; // median wall time of the timed frames of the whole view (render + glFinish)
    double p10Ms = 0.0;   // 10th and 90th percentiles of the same frames: how much the timing is noise
    double p90Ms = 0.0;
    int frames = 0;    // timed frames
    double rmse = 0.0; // the crop against its ground truth (metrics.h)
    double psnrDb = 0.0;
    // Image-aligned slabs this many voxels thick instead of `compositing`'s slices (0: none); post-classified
    // slabs are compared with the post-classified truth.
    double slabThickness = 0.0;
    bool postClassified = false;
};

// The centre square of `view`, `side` pixels a side or the whole of a smaller view, as an image
// plane of its own (cropPlane: the same pixels as in the view).
ImagePlane centreCrop(const ImagePlane& view, int side);
// The side of the crop the editor's Measure and renderer_bench take errors over: a ground truth of
// seconds to a minute on two cores, where the whole view's would take many minutes.
constexpr int kComparisonCropPx = 96;

// `crop` rendered once with `settings`, against `cropTruth`, its ground truth for these settings.
ImageError cropError(SplatRenderer& gl, const ImagePlane& crop, const Image& cropTruth,
                     const SplatSettings& settings);

// The q-quantile (0..1) of `values`, interpolating linearly between ranks: {1, 2, 3, 4} at 0.5 -> 2.5.
// Throws RenderError when `values` is empty.
double percentile(std::vector<double> values, double q);

// Renders `view` `frames` times with `settings` (one untimed frame first, which compiles what they
// need), then `crop` once, and compares it with `cropTruth`, the ground truth of `crop` for them.
FilterMeasurement measureSetting(SplatRenderer& gl, const ImagePlane& view, const ImagePlane& crop,
                                 const Image& cropTruth, SplatSettings settings, int frames);

// The same for image-aligned slabs with `settings` and `slabs`: `drawSlabs` draws a plane in them and
// returns the finished image (a GL slab pass, the CPU oracle); `view` `frames` times, then `crop` once.
// No untimed frame: the slab pass compiles its programs when it is made.
FilterMeasurement measureSlabs(const std::function<Image(const ImagePlane&)>& drawSlabs, const ImagePlane& view,
                               const ImagePlane& crop, const Image& cropTruth, const SplatSettings& settings,
                               const SlabOptions& slabs, int frames);

} // namespace renderer
