// The near layer: kernels whose cutoff ellipsoid reaches the near plane, where EWA's local affine
// projection fails and splatGeometry() leaves them out, integrated exactly along each pixel's centre
// ray from the near plane on, as the ground truth integrates them (ray_kernel.h). Their summed optical
// depth D and extinction-weighted colour E make one layer in front of the splats: alpha 1 - exp(-D),
// colour E / D x alpha, composited over the splatted image (X-ray: E and D added to its sums). Which
// kernels it takes and how a pixel sums them is defined here; the GL path mirrors it
// (renderer/shaders/near_kernels.comp, near_layer.frag). It does not filter with V_h: near kernels
// are many pixels wide.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <array>
#include <cstdint>
#include <vector>

namespace renderer {

// At most this many kernels make a frame's near layer; more (a kernel scale of many voxels, or a very
// wide field of view) are left out and counted (SplatCounters::droppedNear). Each pixel sums them all,
// so the bound is the layer's cost. A camera inside a volume at the default kernel scale 0.7 takes
// about 100-400 (fov 60-120), the near-plane hard case 69.
constexpr int kMaxNearKernels = 1024;

// Whether frames drawn with `settings` in `plane` get a near layer: perspective frames without shading
// or surface splats (those have no ground truth to follow; there near kernels are only left out).
// Orthographic frames splat every kernel whose centre lies in front of the near plane.
bool hasNearLayer(const ImagePlane& plane, const SplatSettings& settings);

// Which kernels belong to the near layer, as a test of a kernel's camera-space centre u: it is not
// splatted (u2 - cutoffDepth <= near, the test of splatGeometry()), part of it lies in front of the near
// plane (u2 + cutoffDepth > near), and its bounding sphere meets the view's frustum widened by the
// ground truth's filter reach (4 px), so that kernels no ray of the image crosses are not counted.
struct NearTest {
    double nearDepth = 0.0;
    double cutoffDepth = 0.0;          // cutoff x the kernel's sigma along u2
    double radius = 0.0;               // cutoff x the kernel's largest sigma
    std::array<glm::dvec3, 4> sides{}; // unit normals of the frustum's side planes through the eye; inside
                                       // where dot(n, u) <= 0
    bool accepts(glm::dvec3 u) const {
        if (u.z - cutoffDepth > nearDepth || !(u.z + cutoffDepth > nearDepth)) return false;
        for (const glm::dvec3& n : sides)
            if (glm::dot(n, u) > radius) return false;
        return true;
    }
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

// Sums of the layer along the centre ray of pixel (x, y): (E, D) = (sum c_k tau_k, sum tau_k).
glm::dvec4 nearLayerSums(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                         const NearKernels& kernels, int x, int y);

} // namespace renderer
