// The reference image splatting approximates (EWA_NOTES "Ground truth"): the absorption-emission
// integral I = int T(s) sum_k c_k g_k r_k(s) ds, dT = -T g(s) ds, along exact perspective (or parallel)
// rays through the same truncated 3D kernels, with no affine approximation, slicing or no-overlap
// assumption; then filtered with V_h by Gaussian-weighted rays around each pixel centre: rays on a grid
// of `supersample` x `supersample` per pixel, weighted by the 1-px Gaussian out to 4 px.
//
// Along a ray each kernel is a 1D Gaussian on an interval (its 3D cutoff ellipsoid), so the optical
// depth and emission of a step have closed forms (erf). The only approximation is how transmittance
// and colour couple inside a step: a step's emission is taken with the step's mean colour. The step
// is halved until the ray's RGBA changes by less than `tolerance` between two step sizes.
#pragma once
#include "renderer/model/gradients.h"
#include "renderer/io/image.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <filesystem>
#include <functional>
#include <string>

namespace renderer {

struct GroundTruthOptions {
    double tolerance = 1e-5;       // per ray: max |RGBA(h) - RGBA(h/2)| that counts as converged
    double initialStepSigmas = 1.0;   // first step, in the smallest kernel sigma
    int maxHalvings = 10;          // then the ray is counted as unconverged and keeps its finest value
    int supersample = 3;           // rays per pixel along each axis for the V_h filter (1..8); the
                                   // filter's weights are exact, the grid decides how well sub-pixel
                                   // detail is resolved (compare s with 2s to see). 0: no filter, one
                                   // ray through each pixel centre (the bare integral, for tests)
    bool postClassified = false;   // the truth of post-classification (post_classification.h): the TF
                                   // applied to the kernels' weighted mean value along the ray, each step's
                                   // value from the kernels' closed-form integrals over it
};

struct GroundTruthStats {
    uint64_t rays = 0;
    uint64_t unconvergedRays = 0;
    double meanHalvings = 0.0;     // step halvings per ray
    double seconds = 0.0;
    bool fromCache = false;
    std::string cacheNote;   // cachedGroundTruth: why the new truth was not kept in the cache ("": it was)
};

// With X-ray compositing the integral is taken without attenuation and shown as the renderer resolves
// X-ray's sum: 1 - exp(-x) of the emission and the optical depth, channel by channel; then filtered alike.
//
// With shading, each kernel's colour is lit along the ray itself (shading.h's Phong with the voxel's
// decoded gradient and the ray's own direction): the truth of the pre-classified shaded model, which
// per-splat shading (the splat centre's direction) and per-fragment shading (the pixel centre's)
// approximate. Post-classified and shaded, each step's classified colour is lit with the step's mean
// gradient (post_classification.h). It needs the scene's gradients (RenderError without them).
//
// Whether frames drawn with `settings` have a ground truth to be compared with: not with surface
// splats, whose flattened kernels are a rendering choice, not the volume's kernels.
bool hasGroundTruth(const SplatSettings& settings);

// The progress callback of gradients.h; here it is called from worker threads (serialised) as rows
// finish, and returning false cancels: the call then throws RenderError("ground truth: cancelled").
using Progress = ProgressCallback;

Image renderGroundTruth(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                        const GroundTruthOptions& options = {}, const Progress& progress = {},
                        GroundTruthStats* stats = nullptr);

// Key of everything the reference depends on: voxel classes, LUT, spacing, camera, size, kernel
// scale, cutoff, density, X-ray or not, and the options (16 hex digits).
std::string groundTruthKey(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                           const GroundTruthOptions& options);
// $SPLATLAB_CACHE_DIR, else $XDG_CACHE_HOME/splatlab/reference, else ~/.cache/splatlab/reference.
std::filesystem::path defaultGroundTruthCacheDir();
// The cached reference (an EXR under the key) or a new one, written to the cache atomically. A new one
// that cannot be written (a read-only or full disk, an entry that is a folder) is still returned, with
// the reason in stats->cacheNote: the next run pays the time again, this one keeps its figure. After a
// write the cache is pruned to its budget, the entries used longest ago first (ground_truth_cache.h).
Image cachedGroundTruth(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                        const GroundTruthOptions& options, const std::filesystem::path& cacheDir,
                        const Progress& progress = {}, GroundTruthStats* stats = nullptr);

} // namespace renderer
