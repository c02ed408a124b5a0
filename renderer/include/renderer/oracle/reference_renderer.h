// The CPU oracle: the same splatting pipeline as the GL path, in double precision, multithreaded over
// image rows so the result does not depend on the thread count. Tests compare GL images against it.
#pragma once
#include "renderer/io/image.h"
#include "renderer/math/shading.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

namespace renderer {

struct SplatCounters {
    uint64_t visible = 0;          // voxels of the drawn buckets (transparent ones included)
    uint64_t culledTransparent = 0;// voxel of a drawn bucket whose own class has opacity 0
    uint64_t drawn = 0;            // splats that reached the image
    uint64_t culledNear = 0;       // not splatted: its cutoff ellipsoid reaches the near plane (or lies behind
                                   // it); those in view are integrated along the rays instead (near_layer.h)
    uint64_t culledOffscreen = 0;  // cutoff ellipse misses the image
    uint64_t culledHuge = 0;       // cutoff radius beyond SplatSettings::maxFootprintFraction (when set)
    uint64_t culledDegenerate = 0; // footprint variance not positive definite (det <= 1e-12 px^4)
    uint64_t culledOccluded = 0;   // front to back: every opaque tile under the footprint was opaque
                                   // at the last refresh (not in `drawn`; changes no pixel)
    uint64_t drawnPerMode[3] = {}; // drawn splats by filter: reconstruction, low-pass, EWA
    uint64_t nearLayer = 0;        // of culledNear: in view, integrated along each pixel's ray (near_layer.h)
    uint64_t droppedNear = 0;      // of culledNear: in view but beyond kMaxNearKernels, left out of the image
};

// a += b, count by count (per-thread counts joined).
void addCounters(SplatCounters& a, const SplatCounters& b);

// Per-splat quantities both paths derive from one voxel (the GLSL vertex stage mirrors this).
struct SplatGeometry {
    bool culled = false;
    glm::dvec2 centrePx{0.0};        // pixel position of the projected kernel centre
    glm::dmat2 conic{1.0};           // inverse of the footprint variance
    glm::dvec2 halfExtentPx{0.0};    // bounding box of the cutoff ellipse
    double amplitude = 0.0;          // optical depth at the centre: g_k * voxel volume * peak
};
// The pixels of rows [y0, y1) and columns [0, width) whose centres (i + 0.5) fall inside the bounding
// box of the splat's cutoff ellipse: x in [xa, xb], y in [ya, yb], empty when either is reversed.
struct PixelBox {
    int xa, xb, ya, yb;
};
PixelBox footprintBox(const SplatGeometry& g, int y0, int y1, int width);

// Towards the eye along the ray through pixel (x, y)'s centre, camera space (shading.h's toEyeAt), and
// per-fragment shading there: `colour` lit with the gradient from that direction.
glm::dvec3 toEyeAtPixel(int x, int y, const ImagePlane& plane);
glm::dvec3 shadeAtPixel(glm::dvec3 colour, glm::dvec3 gradientCamera, int x, int y, const ImagePlane& plane,
                        const ShadingParams& params);

// `mode` is the resolved filter (never Adaptive: see classifier.h).
SplatGeometry splatGeometry(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                            uint32_t voxel, double extinction, FilterMode mode, SplatCounters* counters = nullptr);

// Extinction per object unit of a voxel (its opacity, SplatScene::opacityOf, x density / mean spacing).
double voxelExtinction(const SplatScene& scene, const SplatSettings& settings, uint32_t voxel);

// heatmap (optional): the filter-mode heatmap, composited like the image: premultiplied RGBA with
// r, g, b = the share of reconstruction-only, low-pass-only and full EWA splats in the pixel's alpha.
// previousPatchModes (optional): last frame's patchModes(), for SplatSettings::hysteresis.
Image renderReference(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                      SplatCounters* counters = nullptr, Image* heatmap = nullptr,
                      const std::vector<uint8_t>* previousPatchModes = nullptr);

// Per-patch filter of the frame (classifier.h) for the traversal axis: slice-major, then rows of
// patches along the slice's second in-plane axis (index = (slice * nb + pb) * na + pa).
// With hysteresis, `previous` is last frame's result (ignored when its size does not match).
std::vector<uint8_t> patchModes(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                                const std::vector<uint8_t>* previous = nullptr);

} // namespace renderer
