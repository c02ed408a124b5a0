// What the image-aligned slabs (image_slabs.h) prepare before any pixel: each kernel's footprint and
// depth law along the rays, in slab units, in the order of the first slab it reaches. One place for the
// CPU oracle's slabs and the GL pass that composites them on the GPU (gl/image_slabs_gl.h).
#pragma once
#include "renderer/oracle/image_slabs.h"
#include "renderer/oracle/near_layer.h"

#include <functional>

namespace renderer {

struct SlabSplat {
    SplatGeometry geometry;
    glm::dvec3 colour{0.0};       // TF colour, shaded unless shading is per fragment (pre-classified)
    double value = 0.0;           // the voxel's class (post-classified)
    glm::dvec3 gradientCamera{0.0}; // per-fragment or post-classified shading
    double depth = 0.0;           // ray-space depth of the centre: |u|, or u2 orthographic (slab units)
    glm::dvec2 depthSlope{0.0};   // conditional mean's change per pixel of offset: S_xy^-1 S_xyr
    double depthSd = 0.0;         // conditional standard deviation along the ray
    long first = 0, last = -1;    // slabs it can reach anywhere on its footprint
};

struct SlabSetup {
    std::vector<SlabSplat> splats; // not culled, stably sorted by `first`
    long ring = 1;                 // the most slabs one kernel reaches: the slabs a pixel holds open
    long front = 0, back = -1;     // the first and last slab any kernel reaches
    bool post = false, shaded = false;
    bool perFragment = false;      // pre-classified per-fragment shading: each pixel lights the colour
    int stride = 4;                // sums a slab holds at a pixel, the weight last: pre-classified
                                   // (c tau, tau); post-classified (v w, w), shaded (v w, g w, w)
    double perOpacity = 0.0;       // extinctionPerOpacity
    NearKernels near;
    SlabCounters counters;         // splats and slabs; the pixel work is the compositor's to count
};

// Throws RenderError for a supersample outside 0..kMaxSlabSupersample, naming it.
void requireSlabSupersample(int supersample);

// Throws RenderError as renderImageAlignedSlabs does (all but the supersample and the CPU's ring budget);
// Cancelled once `interrupted` (asked every few thousand kernels, from worker threads) says so.
SlabSetup prepareSlabs(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                       const SlabOptions& options, const std::function<bool()>& interrupted = {});

} // namespace renderer
