// Per-voxel gradients of a volume, for shading and surface splats: central differences in object
// units (each axis divided by its spacing), computed once per volume on all cores, stored compactly.
// Nothing here uploads to GL; the renderer does not use them yet (shading is a later issue).
#pragma once
#include "renderer/model/volume.h"

#include <functional>
#include <optional>

namespace renderer {

// Gradients quantised to 3 x int16 per voxel: component = q / 32767 * scale. 6 bytes a voxel instead
// of 12; the error is below scale / 65534 per component (about 1e-5 of the largest component).
struct GradientField {
    glm::ivec3 dims{0};
    double scale = 0.0;       // largest |component| in the volume, data units per object unit
    std::vector<int16_t> xyz; // 3 per voxel, x fastest like Volume::values

    glm::dvec3 at(size_t voxel) const {
        const double k = scale / 32767.0;
        return {xyz[3 * voxel] * k, xyz[3 * voxel + 1] * k, xyz[3 * voxel + 2] * k};
    }
    double magnitude(size_t voxel) const { return glm::length(at(voxel)); }
};

// Central differences (v[i+1] - v[i-1]) / (2 spacing) inside, one-sided differences on the faces, 0
// along an axis of size 1; non-finite neighbours give 0 for that component. Two passes over z-slabs in
// parallel (oneTBB): the largest component, then the quantised field. Returns std::nullopt, having
// stopped within one batch of slices, when `progress` returns false.
std::optional<GradientField> computeGradients(const Volume& volume, const ProgressCallback& progress = {});

struct GradientStats {
    double min = 0, mean = 0, p99 = 0, max = 0; // of the magnitudes, data units per object unit
};
GradientStats gradientMagnitudeStats(const GradientField& field);

} // namespace renderer
