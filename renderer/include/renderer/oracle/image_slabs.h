// Image-aligned sheet buffers (issue 37; 000's future work, 004 sec. on Neophytou and Mueller 2005), on
// the CPU in double precision: the oracle of the GL pass (renderer/gl/image_slabs_gl.h), which takes the
// same per-kernel set-up (slab_setup.h) and does the pixels' work on the GPU.
//
// Slabs are shells of constant distance from the eye (perspective) or planes of constant depth
// (orthographic), `thickness` voxel spacings (mean spacing) thick, at fixed multiples of it from the
// eye, so they do not move with the volume and a turning view does not switch traversal axis (the
// object-aligned sheets' popping). Shells, not planes, because the third coordinate of EWA's ray space
// (001 eq. 25) is the distance along the ray: a kernel's resampling filter there is a 3D Gaussian whose
// slab sections have closed forms, and each pixel's stretch of ray in a slab has the same length.
//
// Each kernel's share of a slab, at a pixel: in ray space the kernel (plus V_h across the image for
// EWA) is a Gaussian N(mean, [[S_xy, S_xyr], [S_rxy, S_rr]]). Its footprint is the marginal over the
// image (the splats' footprint, splatGeometry), and along the pixel's ray it is the conditional Gaussian
// N(r_c + S_rxy S_xy^-1 d, S_rr - S_rxy S_xy^-1 S_xyr), d the pixel's offset from the projected centre:
// the slab's share is its probability between the slab's ends (erf). The shares of one pixel sum to 1
// (the first and last slab take the tails), so the slabs of one kernel sum to its object-aligned footprint.
// Low-pass-only keeps the kernel's depth profile N(r_c, S_rr) and the V_h footprint.
//
// Pre-classified, composited front to back like the object-aligned sheets: a slab sums (c tau, tau) per
// pixel, then alpha 1 - exp(-sum tau) goes under what lies in front. Filters (adaptive per patch),
// shading, early termination and the near layer as renderReference.
//
// Post-classified (post_classification.h): every kernel, transparent or not, adds its value times its
// weight and its weight (the footprint's line integral through the slab) to the slab (but for those
// whose whole neighbourhood the TF leaves transparent, which change no pixel: post_reach.h); the slab's mean
// value is classified by the TF, and its optical depth is the TF's extinction there times the weight.
// Shaded, each slab's classified colour is lit with the slab's mean gradient (the kernels' voxel
// gradients summed like the values) from the pixel's ray: post_classification.h. Its truth is
// GroundTruthOptions::postClassified. Not with the camera so close that kernels reach the near plane
// (the near layer is pre-classified).
#pragma once
#include "renderer/io/image.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"
#include "renderer/oracle/reference_renderer.h"

namespace renderer {

// The thicknesses a caller may ask for, in voxel spacings: below, one kernel spans thousands of slabs.
constexpr double kMinSlabThickness = 0.05, kMaxSlabThickness = 64.0;

struct SlabCounters {
    SplatCounters splats;          // as renderReference counts them
    uint64_t slabs = 0;            // slabs between the nearest and the farthest kernel's
    uint64_t footprintPixels = 0;  // (kernel, pixel) pairs inside the cutoff: what one sheet writes
    uint64_t slabWrites = 0;       // (kernel, slab, pixel) sums written: each footprint pixel once per slab
                                   // the kernel reaches there
    uint64_t skippedTransparent = 0;   // post-classified kernels skipped: all within reach transparent
                                       // (post_reach.h)
};

struct SlabOptions {
    double thickness = 0.5;        // voxel spacings (mean spacing)
    bool postClassified = false;
    int supersample = 0;           // 0: one sample a pixel. S: S x S samples a pixel resolved by the truth's
                                   // V_h filter (pixel_filter.h), the post-classified truth's own pixel
                                   // filter: its silhouettes and thin TF bands are finer than a pixel.
                                   // S^2 the work; reconstruction-only then leaves V_h to the resolve
    bool cullTransparent = true;   // post-classified: skip kernels whose neighbourhood the TF leaves wholly
                                   // transparent (post_reach.h; the same image). false: the baseline
};
constexpr int kMaxSlabSupersample = 4;

// Throws RenderError for X-ray compositing (order-free: no slabs), surface splats (a rendering choice
// the slabs do not model), a thickness outside [kMinSlabThickness, kMaxSlabThickness], a supersample
// outside 0..kMaxSlabSupersample, and what
// post-classification does not take (requirePostClassifiable; kernels at the near plane).
Image renderImageAlignedSlabs(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                              const SlabOptions& options, SlabCounters* counters = nullptr);

// One kernel's share of each slab along one ray (exposed for tests): the probability of N(mean, sd^2)
// on [slab j, slab j + 1) times `thickness`, for j = first .. first + count - 1, the first and last
// taking the tails. sd 0 puts the whole share in the slab that holds `mean`.
void slabShares(double mean, double sd, double thickness, long first, int count, double* shares);

} // namespace renderer
