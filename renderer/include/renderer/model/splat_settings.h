// Settings every rendering path shares (CPU oracle, GL, editor, CLI); plain data, no behaviour.
#pragma once
#include "renderer/math/ewa.h"
#include "renderer/math/shading.h"

#include <algorithm>
#include <string>

namespace renderer {

enum class Compositing {
    SplatEverySample,   // each splat "over" the image, back to front in slice order (000 fig. 9a)
    XRay,               // additive, order-free (002 eq. 4-5); shown as 1 - exp(-sum)
    SheetBackToFront,   // slice by slice: a slice's splats add into a float sheet (optical depth and
    SheetFrontToBack,   // emission), each sheet is composited in slice order (000 sec. 4, fig. 9b)
};
// "splat-every-sample", "xray", "sheet-back-to-front", "sheet-front-to-back"
const char* compositingName(Compositing c);
Compositing compositingFromName(const std::string& name);   // throws RenderError listing the names

struct SplatSettings {
    double kernelScale = 0.7;   // reconstruction sigma in voxel spacings; 0.7 keeps sum_k r_k within
                                // 1e-3 of 1 on the grid (partition of unity), smaller ripples
    double cutoffSigmas = 3.0;  // footprints are evaluated where (p-c)^T V^-1 (p-c) <= cutoff^2
    double density = 1.0;       // extinction per voxel length (mean spacing) at TF opacity 1
    FilterMode filter = FilterMode::Ewa;
    Compositing compositing = Compositing::SplatEverySample;
    double maxFootprintFraction = 0.0;  // > 0: footprints whose cutoff radius exceeds this times the
                                        // image diagonal are culled and counted as huge. 0 (default):
                                        // none is; a footprint larger than the image covers it (its box
                                        // is clipped to the image), as the truth does (audit issue 33)
    // Adaptive EWA (000 sec. 3.2): magnified patches use reconstruction only, minified ones low-pass
    // only. Paper defaults; cMax <= 0 means 2 (1 + tan^2(fovY/2) (1 + (W/H)^2)), the spread at the image corner.
    double cMin = 0.3;
    double cMax = 0.0;
    int patchSize = 8;                  // slice voxels per patch side; 1 classifies every voxel
    double hysteresis = 0.0;            // > 0: a patch changes filter only when a threshold is crossed
                                        // by this factor (needs last frame's patch modes)

    // Shading (needs the scene's gradients): headlight Phong per splat in the vertex stage, with the
    // splat centre's view direction, or per fragment, with each pixel's ray (000 sec. 4.4).
    enum class Shading { None, PerSplat, PerFragment };
    Shading shading = Shading::None;
    ShadingParams shadingParams;
    // Surface splats (001 sec. 5; needs gradients): voxels whose gradient magnitude (relative to the
    // volume's largest) reaches surfaceGradient get kernels flattened by 1/surfaceFlatten along it.
    double surfaceFlatten = 1.0;        // 1: volume kernels everywhere
    double surfaceGradient = 0.1;

    // Compute only what the scene needs. With opaqueAlpha < 1 splat-every-sample runs front to back
    // (the exact reverse of its back-to-front order: the same image) and, like front-to-back sheets,
    // stops adding to a pixel once its alpha reached opaqueAlpha; >= 1: never, and splat-every-sample
    // runs back to front. What is lost is at most 1 - opaqueAlpha of the pixel. Which pixels are opaque
    // is refreshed every opaqueRefreshSlices slices (in draw order); splats whose every kOpaqueTilePx
    // tile was opaque at the last snapshot (occlusionSlices()) are culled before they are drawn or binned.
    double opaqueAlpha = 0.998;
    int opaqueRefreshSlices = 0;        // 0: auto, opaqueRefreshSlices() below
    bool occlusionCulling = true;       // false keeps hidden splats (early termination still skips their
                                        // pixels): a baseline, and faster tiles on a GPU (docs/speed.md)
    bool drawAllBuckets = false;        // baseline for measurements: every voxel reaches the vertex
                                        // stage, transparent ones are culled there

    // GL only: how splats reach pixels (all give the same image) and what else a frame records.
    // Tiles: compute passes bin the splats to screen tiles and composite each pixel in registers
    // (sheet and X-ray compositing only: a sheet's sum does not depend on the order within a slice).
    // Raster: slice by slice, points where the slice's footprints fit the largest point size, quads
    // otherwise (close up, the near slices).
    // Auto: tiles for sheets and X-ray (faster on every machine measured), raster for
    // splat-every-sample; raster also for a frame where one slice's tile lists do not fit
    // (tiledSplatting()).
    enum class Primitive { Auto, Raster, Points, Quads, Tiles };
    Primitive primitive = Primitive::Auto;
    bool heatmap = false;               // also render the filter-mode heatmap (renderers' readback)
    bool counters = false;              // count splats per mode and per guard on the GPU (atomics)
};

// Side of the square pixel tiles of the opaque-tile map behind occlusion culling.
// The names the command line and sessions use: "none", "per-splat", "per-fragment"; "auto", "raster",
// "points", "quads", "tiles". FromName throws RenderError listing them.
const char* shadingName(SplatSettings::Shading s);
SplatSettings::Shading shadingFromName(const std::string& name);
const char* primitiveName(SplatSettings::Primitive p);
SplatSettings::Primitive primitiveFromName(const std::string& name);

constexpr int kOpaqueTilePx = 8;
// The values of each numeric setting that a session or the command line accepts, one place for both
// (the Settings panel's sliders span narrower, everyday ranges). Beyond them a frame is all clear or
// all opaque, a footprint NaN, or a kernel too thin or too wide to mean anything.
struct SettingRange {
    double lo, hi;
    bool holds(double x) const { return x >= lo && x <= hi; }   // false for NaN
};
constexpr SettingRange kKernelScaleRange{0.05, 10.0};   // voxel spacings
constexpr SettingRange kCutoffRange{0.5, 10.0};         // sigmas
constexpr SettingRange kDensityRange{1e-6, 1e6};
constexpr SettingRange kCMinRange{0.01, 10.0};
constexpr SettingRange kCMaxRange{0.0, 100.0};          // 0: the paper's 2 (1 + tan^2(fovY/2) (1 + (W/H)^2))
constexpr SettingRange kPatchSizeRange{1, 256};         // voxels; whole numbers
constexpr SettingRange kHysteresisRange{0.0, 10.0};
constexpr SettingRange kOpaqueAlphaRange{0.01, 1.0};    // 1: never opaque
constexpr SettingRange kOpaqueRefreshRange{0, 4096};    // slices; 0: auto; whole numbers
constexpr SettingRange kSurfaceFlattenRange{1.0, 1e6};  // 1: volume kernels
constexpr SettingRange kSurfaceGradientRange{0.0, 1.0}; // fraction of the largest gradient
// Side of the square screen tiles of tiled splatting (one compute workgroup each).
constexpr int kSplatTilePx = 8;

// True when the frame is composited front to back (early termination applies).
bool frontToBack(const SplatSettings& settings);
// Whether the frame composites with tiles' semantics: primitive Tiles, or Auto with sheets or X-ray.
// Per-splat occlusion culling, its counter and the automatic refresh interval follow from it, on the
// GPU and in the CPU oracle alike. (Auto falls back to the rasteriser where one slice's lists do not
// fit; that frame keeps these semantics: same image and counters, only slower.)
inline bool tiledSplatting(const SplatSettings& s) {
    return s.primitive == SplatSettings::Primitive::Tiles ||
           (s.primitive == SplatSettings::Primitive::Auto && s.compositing != Compositing::SplatEverySample);
}

// Slices between refreshes of the opaque pixels. Auto: every slice for tiled splatting, whose pixels
// keep their alpha in registers (a refresh is free); every 8 for the rasteriser, where a refresh is a
// pass that drains the pipeline (8 was the fastest on llvmpipe and the H100).
inline int opaqueRefreshSlices(const SplatSettings& s) {
    if (s.opaqueRefreshSlices <= 0) return tiledSplatting(s) ? 1 : 8;
    return s.opaqueRefreshSlices;
}

// Slices between the snapshots of the opaque-tile map that occlusion culling reads (a splat is culled
// when every tile under its box was opaque at the last snapshot). The rasteriser takes one at each
// refresh. Tiled splatting bins chunks of at least kTileChunkSlices slices (a multiple of the refresh),
// each against the map the chunks before it left: a chunk is several passes and a wait, so not a slice.
// 8 against 16 on llvmpipe: bonsai 2-4 % and engine 7 % faster, headsq the same
// (docs/performance.md, "Tiled splatting").
constexpr int kTileChunkSlices = 8;
inline int occlusionSlices(const SplatSettings& s) {
    const int refresh = opaqueRefreshSlices(s);
    return tiledSplatting(s) ? refresh * ((kTileChunkSlices + refresh - 1) / refresh) : refresh;
}

// The chunk that starts at slice `start` (in draw order) after one of `chunk` slices, given whether
// any tile of the map is opaque there. The first two chunks are occlusionSlices(). With tiles'
// semantics, while no tile is opaque after those (nothing to cull against) each chunk doubles, up
// to four times the first, so a mostly transparent view pays for few chunks; once a tile is opaque
// (it stays so, front to back) chunks are occlusionSlices() again. Doubling from the first chunk on
// cost bonsai culling (617 k splats culled instead of 776 k, 4 % slower). The GPU and the CPU oracle
// follow it alike.
inline int maxOcclusionChunk(const SplatSettings& s) { return (tiledSplatting(s) ? 4 : 1) * occlusionSlices(s); }
inline int nextOcclusionChunk(const SplatSettings& s, int start, int chunk, bool anyOpaque) {
    const int first = occlusionSlices(s);
    if (anyOpaque || !tiledSplatting(s) || start < 2 * first) return first;
    return std::min(2 * chunk, maxOcclusionChunk(s));
}

// Shading and surface splats read the scene's gradients.
bool needsGradients(const SplatSettings& s);
// Throws RenderError naming the scene when `s` needs gradients the scene lacks, or for a surface
// flatten below 1. Both renderers call it before a frame.
void requireGradients(const SplatSettings& s, bool sceneHasGradients, const std::string& sceneName);

} // namespace renderer
