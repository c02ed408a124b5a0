// What a pixel shows: the voxel its ray meets, so that a user pointing at the view can find that voxel's
// value on the transfer function's axis. CPU only, one ray; it draws nothing.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <optional>

namespace renderer {

struct PixelProbe {
    glm::ivec3 voxel{0};    // grid indices
    double alpha = 0.0;     // opacity gathered along the ray up to and including the voxel
    double depth = 0.0;     // the voxel centre's camera depth (u2), object units
};

// Marches the ray through pixel position `pixel` (x right, y down; pixel (i, j) covers [i, i+1) x [j, j+1))
// front to back through the scene's grid, in steps of half its smallest spacing, taking each step's
// nearest voxel: extinction by its class as the splats take it (voxelExtinction), without their kernels.
// Returns the first voxel at which the gathered opacity reaches `alphaAt` (0.5: where a surface shows),
// nothing where the ray misses the grid or stays more transparent than that.
std::optional<PixelProbe> probePixel(const SplatScene& scene, const SplatSettings& settings, const ImagePlane& plane,
                                     glm::dvec2 pixel, double alphaAt = 0.5);

} // namespace renderer
