// Which kernels a post-classified frame can skip without changing a pixel (image_slabs.h). Post-classified,
// every kernel, transparent or not, adds its value to the slabs it reaches, since a transparent value pulls
// a slab's mean down. But a slab at a pixel is only ever reached by kernels within `reach` of one another
// (twice a kernel's reach in ray space, plus the slab): if every voxel within `reach` of kernel k has a
// value in a range where the TF is transparent, every slab k reaches has its mean in that range, so it is
// transparent with k or without it. A CT's air and, under a bone TF, its soft tissue away from bone are
// such kernels: most of a scan.
//
// Conservative by construction: voxels are tested in 2^3 bricks, each against the value range of the
// bricks within reach (grown by a brick and one class either side, for rounding); a kernel is kept unless
// the TF is transparent over the whole range. The images with and without the culling agree exactly
// (tests/unit/test_post_reach.cpp).
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <cstdint>
#include <vector>

namespace renderer {

// Object units within which two kernels can share a slab at a pixel of `plane`: twice one kernel's reach
// (1.1 x cutoff x sqrt(3 sigma^2 + p^2), sigma the largest kernel axis, p the farthest voxel's pixel
// size, plus a slab for rounding), plus the slab.
double postReach(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings, double slabUnits);

// Per voxel (x fastest): 1 where the kernel may change a post-classified pixel, 0 where every value
// within `reach` object units is transparent under the scene's LUT.
std::vector<uint8_t> kernelsNearVisible(const SplatScene& scene, double reach);

} // namespace renderer
