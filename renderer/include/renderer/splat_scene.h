// The pre-classified scene both renderers consume: per-voxel LUT classes, the LUT, and per traversal
// axis the visible voxels in slice order. One definition of "visible" and of draw order, so the CPU
// oracle and the GL path composite the very same splats in the very same order.
#pragma once
#include "renderer/camera.h"
#include "renderer/transfer_function.h"
#include "renderer/volume.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace renderer {

struct SplatScene {
    std::string name;                    // the volume's name, for messages
    glm::ivec3 dims{0};
    glm::dvec3 spacing{1.0};
    glm::dvec3 origin{0.0};
    glm::dvec3 centre{0.0};
    double radius = 0.0;                 // bounding radius of the voxel centres
    ValueRange window;                   // data values mapped to TF domain [0,1]
    std::vector<uint16_t> classes;       // per voxel, x fastest: index into lut
    Lut lut;
    // Per axis (0 = x, 1 = y, 2 = z): linear indices of voxels whose class has opacity > 0, sorted by
    // their coordinate along that axis, ties by linear index; sliceStart[a][s] is where slice s begins.
    std::array<std::vector<uint32_t>, 3> visible;
    std::array<std::vector<uint32_t>, 3> sliceStart;

    size_t visibleCount() const { return visible[2].size(); }
    glm::dvec3 positionOf(uint32_t index) const;
};

// Classifies every voxel over `window` (the volume's range when lo == hi) and builds the lists.
SplatScene buildSplatScene(const Volume& volume, const TransferFunction& tf, ValueRange window = {});
// A TF edit: re-bakes the LUT and rebuilds the visible lists (issue 4 replaces this with buckets).
void setTransferFunction(SplatScene& scene, const TransferFunction& tf);

// Splat-every-sample draws along the object axis most parallel to the view, far slices first.
struct Traversal {
    int axis = 2;
    bool descending = false;   // true: walk the axis list from its end (highest coordinate first)
};
Traversal chooseTraversal(const ImagePlane& plane);

} // namespace renderer
