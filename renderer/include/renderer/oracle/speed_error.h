// Speed against error for one view: every filter x compositing mode timed with repeats and compared
// with the ground truth (filter_comparison.h does one setting), and the Pareto front of the result.
// The editor's Measure steps through speedErrorSettings() itself, a setting per UI frame; `splatlab
// report` calls measureSpeedAgainstError(). Drawing the chart is theirs.
#pragma once
#include "renderer/oracle/filter_comparison.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/image_slabs.h"

#include <filesystem>
#include <span>
#include <vector>

namespace renderer {

// `base` once for every filter x compositing mode the editor offers (its other settings kept; tiles,
// which composite sheets and X-ray only, give way to auto for splat-every-sample). Empty when `base`
// has no ground truth (hasGroundTruth: surface splats).
std::vector<SplatSettings> speedErrorSettings(const SplatSettings& base);

// The crop's ground truths: one serves every attenuating compositing mode, X-ray has its own
// (groundTruthKey tells them apart), and post-classified slabs theirs.
struct CropTruths {
    Image attenuating, xray;
    Image postClassified;   // where asked for (cropTruths' `postClassified`)
    const Image& of(const SplatSettings& settings) const {
        return settings.compositing == Compositing::XRay ? xray : attenuating;
    }
    const Image& ofSlabs(const SlabOptions& slabs) const { return slabs.postClassified ? postClassified : attenuating; }
};
// The attenuating and X-ray truths and, with `postClassified`, the post-classified one, from `cacheDir`
// or computed there; `progress` goes 0..1 over them.
CropTruths cropTruths(const SplatScene& scene, const ImagePlane& crop, const SplatSettings& base,
                      const GroundTruthOptions& options, const std::filesystem::path& cacheDir,
                      const ProgressCallback& progress = {}, bool postClassified = false);

// measureSetting() for each of speedErrorSettings(base), `repeats` timed frames each, in that order.
std::vector<FilterMeasurement> measureSpeedAgainstError(SplatRenderer& gl, const ImagePlane& view,
                                                        const ImagePlane& crop, const CropTruths& truths,
                                                        const SplatSettings& base, int repeats);

// Which points are on the Pareto front, fastest for their error: a point is off it when another is at
// least as fast (median frame time) and at least as accurate (PSNR) and better in one of the two.
// Equal points do not push each other off: both stay on. Only points measured against the same ground
// truth compete (sameGroundTruth): X-ray's error is against an image of its own, so it has its own front,
// as post-classified slabs have.
bool sameGroundTruth(const FilterMeasurement& a, const FilterMeasurement& b);
// Which truth a measurement was compared with, in the order the charts list their fronts: 0 the
// attenuating modes', 1 X-ray's, 2 the post-classified one (post-classified slabs).
int groundTruthKind(const FilterMeasurement& m);
std::vector<bool> paretoFront(std::span<const FilterMeasurement> points);

} // namespace renderer
