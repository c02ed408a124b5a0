// The near layer: kernels whose cutoff ellipsoid reaches the near plane, where EWA's local affine
// projection fails, and those just behind them (within kNearLayerDepths cutoff depths of the plane),
// where it still errs; splatGeometry() leaves them out. Each is integrated exactly along each pixel's
// centre ray from the near plane on, as the ground truth integrates it (ray_kernel.h). Two sheets, each
// its kernels' summed optical depth D and extinction-weighted colour E (alpha 1 - exp(-D), colour
// E / D x alpha): the kernels that reach the plane over those behind them, and both over the splatted
// image (X-ray: every E and D added to its sums). Which
// kernels it takes and how a pixel sums them is defined here; the GL path mirrors it
// (renderer/shaders/near_kernels.comp, near_layer.frag). It does not filter with V_h: near kernels
// are many pixels wide.
#pragma once
#include "renderer/io/image.h"
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <array>
#include <cstdint>
#include <vector>

namespace renderer {

// The layer takes kernels whose centre lies within this many cutoff depths (cutoff x the kernel's sigma
// along u2) of the near plane. 1 takes only those that reach it: the splats behind them then overestimate
// the optical depth by 7-9 % (camera inside a volume); 2 leaves 0.5 % (docs/accuracy.md "Near the eye").
constexpr double kNearLayerDepths = 2.0;

// At most this many kernels make a frame's near layer; more (a kernel scale of many voxels, or a very
// wide field of view) are left out and counted (SplatCounters::droppedNear). Each pixel sums them all,
// so the bound is the layer's cost. A camera inside a volume at the default kernel scale 0.7 and a 60
// degree field of view takes about 235 (the voxel-centre view of nearEyeCases()).
constexpr int kMaxNearKernels = 1024;

// Whether frames drawn with `settings` in `plane` get a near layer: perspective frames without shading
// or surface splats (the layer's kernels take the LUT's colour; there near kernels are only left out).
// Orthographic frames splat every kernel whose centre lies in front of the near plane.
bool hasNearLayer(const ImagePlane& plane, const SplatSettings& settings);

// The reach splatGeometry() and the splat stage keep from the near plane, in sigmas along u2: a kernel
// with u2 - reach sigma_u2 <= near is not splatted. Cutoff x kNearLayerDepths with a near layer, else
// the cutoff (those kernels are then dropped).
double splatNearReach(const ImagePlane& plane, const SplatSettings& settings);

// Which kernels belong to the near layer, as a test of a kernel's camera-space centre u: it is not
// splatted (u2 - reachDepth <= near, the test of splatGeometry()), part of it lies in front of the near
// plane (u2 + cutoffDepth > near), and its bounding sphere meets the view's frustum widened by the
// ground truth's filter reach (4 px), so that kernels no ray of the image crosses are not counted.
struct NearTest {
    double nearDepth = 0.0;
    double cutoffDepth = 0.0;          // cutoff x the kernel's sigma along u2
    double reachDepth = 0.0;           // splatNearReach() x the kernel's sigma along u2
    double radius = 0.0;               // cutoff x the kernel's largest sigma
    std::array<glm::dvec3, 4> sides{}; // unit normals of the frustum's side planes through the eye; inside
                                       // where dot(n, u) <= 0
    bool accepts(glm::dvec3 u) const {
        if (u.z - reachDepth > nearDepth || !(u.z + cutoffDepth > nearDepth)) return false;
        for (const glm::dvec3& n : sides)
            if (glm::dot(n, u) > radius) return false;
        return true;
    }
    // Of the accepted: in the front sheet, its cutoff ellipsoid reaching the near plane.
    bool front(glm::dvec3 u) const { return !(u.z - cutoffDepth > nearDepth); }
};
NearTest nearTest(glm::dvec3 spacing, const ImagePlane& plane, const SplatSettings& settings);

// The voxels whose kernels `test` may accept: a box of grid indices around the eye (empty: lo > hi).
struct VoxelBox {
    glm::ivec3 lo{0}, hi{-1};
    bool empty() const { return glm::any(glm::greaterThan(lo, hi)); }
    uint64_t count() const {
        return empty() ? 0
                       : uint64_t(hi.x - lo.x + 1) * uint64_t(hi.y - lo.y + 1) * uint64_t(hi.z - lo.z + 1);
    }
};
VoxelBox nearCandidates(glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing, const ImagePlane& plane,
                        const NearTest& test);

struct NearKernels {
    std::vector<uint32_t> voxels; // in grid order, at most kMaxNearKernels
    uint64_t dropped = 0;         // accepted beyond kMaxNearKernels
};
// The visible (opacity > 0) kernels of the near layer; none without one (hasNearLayer).
NearKernels findNearKernels(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings);

// Sums of the layer's two sheets along the centre ray of pixel (x, y): (E, D) = (sum c_k tau_k, sum tau_k)
// over the front sheet's kernels, and over the back sheet's.
struct NearSums {
    glm::dvec4 front{0.0}, back{0.0};
};
NearSums nearLayerSums(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                       const NearKernels& kernels, int x, int y);

// The layer in front of an image of premultiplied RGBA (width x height x 4, rows from the top) that holds
// everything behind it: its back sheet, then its front sheet, each "over" the image; with X-ray
// compositing, added to X-ray's sums instead. Parallel over rows; nothing without kernels.
void compositeNearLayer(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                        const NearKernels& kernels, std::vector<double>& rgba);
// compositeNearLayer over `rgba` (width x height of the plane), as a float image: how the image-aligned
// slabs, on the CPU and on the GL, finish.
Image imageWithNearLayer(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                         const NearKernels& kernels, std::vector<double> rgba);

} // namespace renderer
