// Pre-classification: voxel classes, the LUT and the per-axis visible lists (see splat_scene.h).
#include "renderer/splat_scene.h"

#include "renderer/errors.h"

#include <cmath>

namespace renderer {

glm::dvec3 SplatScene::positionOf(uint32_t index) const {
    const uint32_t x = index % uint32_t(dims.x);
    const uint32_t y = (index / uint32_t(dims.x)) % uint32_t(dims.y);
    const uint32_t z = index / (uint32_t(dims.x) * uint32_t(dims.y));
    return origin + spacing * glm::dvec3(x, y, z);
}

SplatScene buildSplatScene(const Volume& volume, const TransferFunction& tf, ValueRange window) {
    if (volume.voxelCount() == 0 || volume.values.size() != volume.voxelCount())
        throw RenderError("volume '" + volume.name + "' has no voxels");
    if (volume.voxelCount() > size_t(UINT32_MAX))
        throw RenderError("volume '" + volume.name + "' has more than 2^32 voxels");
    SplatScene s;
    s.name = volume.name;
    s.dims = volume.dims;
    s.spacing = volume.spacing;
    s.origin = volume.origin;
    s.centre = volume.centre();
    s.radius = volume.boundingRadius();
    s.window = (window.hi > window.lo) ? window : volume.range;
    s.classes.resize(volume.voxelCount());
    for (size_t i = 0; i < s.classes.size(); ++i) s.classes[i] = classOf(volume.values[i], s.window.lo, s.window.hi);
    setTransferFunction(s, tf);
    return s;
}

void setTransferFunction(SplatScene& s, const TransferFunction& tf) {
    s.lut = bakeLut(tf);
    const glm::ivec3 d = s.dims;
    for (int axis = 0; axis < 3; ++axis) {
        // Counting sort by the coordinate along `axis`; scanning in linear order keeps ties by index.
        std::vector<uint32_t> count(size_t(d[axis]) + 1, 0);
        for (int z = 0; z < d.z; ++z)
            for (int y = 0; y < d.y; ++y)
                for (int x = 0; x < d.x; ++x) {
                    const size_t i = (size_t(z) * d.y + y) * d.x + x;
                    if (s.lut[s.classes[i]].a > 0.0f) ++count[size_t(glm::ivec3(x, y, z)[axis]) + 1];
                }
        for (size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
        s.sliceStart[axis] = count;
        auto& list = s.visible[axis];
        list.assign(count.back(), 0);
        for (int z = 0; z < d.z; ++z)
            for (int y = 0; y < d.y; ++y)
                for (int x = 0; x < d.x; ++x) {
                    const size_t i = (size_t(z) * d.y + y) * d.x + x;
                    if (s.lut[s.classes[i]].a > 0.0f) list[count[size_t(glm::ivec3(x, y, z)[axis])]++] = uint32_t(i);
                }
    }
}

Traversal chooseTraversal(const ImagePlane& plane) {
    const glm::dvec3 v = plane.viewDirObject;
    Traversal t;
    t.axis = (std::abs(v.x) >= std::abs(v.y) && std::abs(v.x) >= std::abs(v.z)) ? 0
             : (std::abs(v.y) >= std::abs(v.z))                                  ? 1
                                                                                  : 2;
    // Back to front: when the view points along +axis, the far slices have the highest coordinate.
    t.descending = v[t.axis] > 0.0;
    return t;
}

} // namespace renderer
