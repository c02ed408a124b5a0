// The scalar volume every path shares: dims, spacing, origin, values in the data's own units.
// It owns no GL objects and knows no file format (volume_io.h reads files into it).
#pragma once
#include "renderer/math/glm_config.h"
#include "renderer/model/voxel_values.h"

#include <algorithm>
#include <cstddef>
#include <climits>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace renderer {

// The largest volume SplatLab opens: one limit for the readers and the renderer, so a file is refused
// from its header, before anything is read, rather than after loading (a 1 GiB raw once took 22 s and
// 4.1 GiB to be refused). The GPU reads a voxel's packed gradient at byte 3 x its index, kept within a
// signed int as drivers address storage buffers: INT32_MAX / 3 voxels (715,827,882: 894^3, or 1024 x
// 1024 x 682). The lists hold a voxel's place in its slice in 16 bits, hence 65535 voxels along an axis.
constexpr size_t kMaxVoxels = size_t(INT32_MAX) / 3;
constexpr int kMaxAxisVoxels = 65535;

struct ValueRange {
    float lo = 0.0f;
    float hi = 0.0f;
};

struct Histogram {
    ValueRange range;                 // the bins cover [range.lo, range.hi]
    std::vector<uint64_t> counts;     // equal-width bins
};

// Whether `m` is a rotation (orthonormal columns, determinant +1), within 1e-6.
bool isRotation(const glm::dmat3& m);

// Long work (reading a volume, its gradients) calls this with the fraction done (0..1, non-decreasing),
// from the thread doing the work, between chunks of it. Return false to cancel.
using ProgressCallback = std::function<bool(double fraction)>;

struct Volume {
    std::string name;                 // shown in the UI and in `info`; usually the file stem
    glm::ivec3 dims{0};               // voxels along x, y, z
    glm::dvec3 spacing{1.0};          // distance between voxel centres, object units (mm for CT)
    glm::dvec3 origin{0.0};           // object-space position of voxel (0,0,0)
    // Unit vector of each index axis in the file's world frame (columns: x, y, z), from NRRD space
    // directions, a MetaImage TransformMatrix or a NIfTI qform/sform. Object space is index x spacing +
    // origin; alignedToWorldAxes() reorders the voxels so that what is left here is a rotation, which the
    // image plane applies (SplatScene::axes), and resamples sheared ones onto the world's.
    glm::dmat3 directions{1.0};
    bool resampled = false;           // sheared axes resampled onto the world's (alignedToWorldAxes)
    VoxelType type = VoxelType::F32;  // the type the values had on disk (values.type() unless rescaled)
    VoxelValues values;               // x fastest, then y, then z; in the data's own units
    ValueRange range;                 // min and max of the finite values (see updateRange)

    size_t voxelCount() const { return size_t(dims.x) * size_t(dims.y) * size_t(dims.z); }
    // The rotation the image plane turns the volume by: `directions` where they are one, else none.
    glm::dmat3 drawnAxes() const { return isRotation(directions) ? directions : glm::dmat3(1.0); }
    // Axes the renderer does not apply (sheared, or mirrored where alignedToWorldAxes did not run): the
    // picture may be turned against the file's world frame, so the tools say so.
    bool axesNotDrawn() const { return !isRotation(directions); }
    size_t index(int x, int y, int z) const {
        return (size_t(z) * size_t(dims.y) + size_t(y)) * size_t(dims.x) + size_t(x);
    }
    float at(int x, int y, int z) const { return values[index(x, y, z)]; }
    glm::dvec3 positionOf(int x, int y, int z) const { return origin + spacing * glm::dvec3(x, y, z); }
    glm::dvec3 centre() const { return origin + 0.5 * spacing * glm::dvec3(dims - 1); }
    // Radius of the sphere around centre() that holds every voxel centre; at least half a voxel's
    // diagonal, so a one-voxel volume still has a size to frame.
    double boundingRadius() const {
        return 0.5 * std::max(glm::length(spacing * glm::dvec3(dims - 1)), glm::length(spacing));
    }
};

// Whether `directions` are the world axes mirrored or swapped (each column +-1 on one axis, within
// 1e-6), which alignedToWorldAxes applies exactly.
bool axesAlignable(const glm::dmat3& directions);
// The volume with its voxels reordered (dims, spacing and origin to match) so that its axes are drawn
// in the file's world frame (its left stays left). Axes within 2e-3 of orthonormal (a header's rounded
// cosines) are first replaced by the orthonormal axes nearest them; then
// - axes that are the world's mirrored or swapped (axesAlignable; as scanners store them) become x, y, z;
// - oblique axes that mirror (determinant -1) have x reversed, which leaves a rotation (drawnAxes);
// - sheared axes (further from orthonormal) are resampled onto the world's (resampledOntoWorldAxes).
Volume alignedToWorldAxes(Volume volume);
// The volume resampled (trilinear, in its index space) onto a grid along the world axes that holds every
// voxel centre: each world axis takes the step of the index axis most along it, projected onto it (a CT
// tilted about x keeps its pixel size and its slice distance along z). Grid points outside the scan take
// the data's minimum (air in CT). Throws LoadError naming the volume where the axes are degenerate or
// the grid would hold more than 8 times the file's voxels (at least 1 M; at most kMaxVoxels).
Volume resampledOntoWorldAxes(const Volume& volume);
// The grid resampledOntoWorldAxes puts `volume` on: dims, spacing and origin, no values (what `info`
// prints); throws as it does.
Volume worldGrid(const Volume& volume);

// How a coarse voxel gets its value from its (up to 8) finite fine voxels. Mean: their mean. PickOne: one
// of them, chosen by a hash of the coarse voxel's index: then for any TF the coarse voxels' classified
// extinction and extinction-weighted colour average those of the fine voxels (in expectation), where a
// mean of values can leave a sharp TF's band and lose a thin feature.
enum class Downsample { Mean, PickOne };
// The volume at half resolution, for the editor's levels of detail (8 times fewer splats): voxel i from
// the finite values of fine voxels 2i and 2i + 1 on each axis (NaN where none is), at their centre,
// spacing doubled. An axis of one voxel stays as it is. An odd axis's last coarse voxel holds one fine
// layer and sits half a fine voxel beyond it (a preview's shortcut).
Volume halfResolution(const Volume& volume, Downsample how = Downsample::Mean);
// The density that gives `coarse` the extinction per unit length that `density` gives `fine`: a TF
// opacity is extinction per mean voxel spacing (SplatSettings::density).
double densityFor(const Volume& coarse, const Volume& fine, double density);

// Recomputes volume.range from the finite values (NaN and Inf are skipped).
void updateRange(Volume& volume);
// Equal-width histogram of the finite values over volume.range.
Histogram computeHistogram(const Volume& volume, int bins);

} // namespace renderer
