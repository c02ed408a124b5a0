// The adaptive classifier of 000 sec. 3.2 in pixel units (EWA_NOTES errata): a kernel of sigma r_k
// at depth u2 projects to R_k = r_k fPx / u2 pixels; with the low-pass sigma r_h = 1 px it takes
// reconstruction only when R_k > r_h / c_min, low-pass only when R_k < r_h / c_max, EWA otherwise.
// Rectilinear kernels are not symmetric: the reconstruction test uses the smallest sigma and the
// low-pass test the largest, so each shortcut is taken only where it holds along every axis.
// A patch takes a shortcut only when all four corner voxels agree (000 sec. 4.1).
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <optional>

namespace renderer {

struct AdaptiveThresholds {
    double reconstructionAbovePx = 0.0;   // r_h / c_min: R_k(smallest sigma) above it -> reconstruction
    double lowPassBelowPx = 0.0;          // r_h / c_max: R_k(largest sigma) below it -> low-pass
    double sigmaMin = 0.0, sigmaMax = 0.0;   // kernel sigmas in object units
};
AdaptiveThresholds adaptiveThresholds(glm::dvec3 spacing, const ImagePlane& plane, const SplatSettings& s);

// The filter of one kernel centred at camera depth u2. Hysteresis (optional): given last frame's
// filter `previous` (Adaptive: none), a threshold is crossed only by the factor 1 + hysteresis, so
// a kernel near a threshold keeps its filter while the camera moves a little (no flicker).
FilterMode classifyDepth(double u2, const ImagePlane& plane, const AdaptiveThresholds& t,
                         FilterMode previous = FilterMode::Adaptive, double hysteresis = 0.0);

// Where the filter changes with depth (no hysteresis): a kernel nearer than reconstructionNearer
// takes reconstruction only; else one farther than lowPassFarther takes low-pass only; else EWA.
// Orthographic views have no such depth, one filter holds everywhere: the two are then 0 or infinity.
struct FilterDepths {
    double reconstructionNearer = 0.0, lowPassFarther = 0.0;
};
FilterDepths filterDepths(const AdaptiveThresholds& t, const ImagePlane& plane);

// The filter every patch of a dims-sized volume at origin/spacing takes in this view, whatever their
// last frame's filters and the hysteresis, when the volume's depth range decides it with a margin for
// the GPU's float classifier; none when patches may differ. A frame it decides can run that filter's
// code instead of looking up each voxel's patch.
std::optional<FilterMode> uniformAdaptiveFilter(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing,
                                                const ImagePlane& plane, const SplatSettings& s);

// Whether every footprint a frame drawn with `drawn` (the filter in force: uniformAdaptiveFilter's, else
// s.filter) gives a dims-sized volume at origin/spacing holds at least the 1-px low-pass, M >= I, so
// that every entry of its conic is at most 1 (the tile composite's recurrence needs it). Low-pass and
// EWA add the low-pass. Reconstruction only takes the projected kernel alone, at least its smallest
// sigma's size in pixels squared (the projection stretches no direction less than f / u2): enough where
// that size reaches a pixel at the farthest voxel, or, adaptive, where only kernels over 1 / c_min px
// (less hysteresis) take it and c_min (1 + hysteresis) <= 1. Surface splats flatten kernels below that.
bool footprintsHoldThePixel(FilterMode drawn, glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing,
                            const ImagePlane& plane, const SplatSettings& s);

// The patches of the slices across `axis`: `columns` along axis a1 = (axis+1)%3, `rows` along
// a2 = (axis+2)%3, slice-major. The one layout of the CPU's and the GPU's per-patch filters.
struct PatchGrid {
    int axis = 2, size = 8, columns = 0, rows = 0, slices = 0;
    size_t count() const { return size_t(columns) * size_t(rows) * size_t(slices); }
    size_t indexOf(glm::ivec3 voxel) const {
        return (size_t(voxel[axis]) * size_t(rows) + size_t(voxel[(axis + 2) % 3] / size)) * size_t(columns) +
               size_t(voxel[(axis + 1) % 3] / size);
    }
    bool operator==(const PatchGrid&) const = default;
};
PatchGrid patchGrid(glm::ivec3 dims, int axis, int patchSize);

// The filter of the patch holding `voxel` in its slice along `axis` (settings.patchSize voxels a
// side, clipped at the volume's faces), from the depths of the patch's four corner voxels.
// `previous`/`hysteresis`: the patch's filter last frame, as for classifyDepth.
FilterMode classifyPatch(const SplatScene& scene, const ImagePlane& plane, const AdaptiveThresholds& t,
                         int patchSize, int axis, uint32_t voxel, FilterMode previous = FilterMode::Adaptive,
                         double hysteresis = 0.0);

} // namespace renderer
