// The pre-classified scene both renderers consume: per-voxel LUT classes, the LUT, and per traversal
// axis the voxels of each slice bucketed by quantised class (000 sec. 4.3, list-based classification).
// A TF edit re-bakes the LUT and only changes which buckets are drawn: the lists never change. One
// definition of the draw order, so the CPU oracle and the GL path composite the same splats in the
// same order.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/math/shading.h"
#include "renderer/model/gradients.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/volume.h"

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace renderer {

// Classes fall into kBuckets buckets of kLutSize / kBuckets consecutive classes each.
constexpr int kBucketShift = 6;
constexpr int kBuckets = kLutSize >> kBucketShift;
// A slice is cut into tiles of at most this many in-slice positions, so a list entry fits 16 bits.
constexpr uint32_t kTileVoxels = 65536;

// A bucket holding more than 1 / kDenseShare of a tile's positions is drawn by walking the tile, not
// listed. Eighths, measured against halves: noisy headsq's lists take 4.71 GPU bytes a voxel instead of
// 8.16, engine's 3.57 instead of 4.72, at the same frame time within the VM's noise (also with every
// bucket visible), since a walked bucket is mostly air, which a TF leaves transparent.
constexpr uint32_t kDenseShare = 8;

// The voxels of one bucket in one tile of one slice. Sparse runs list their voxels as 16-bit offsets
// from the tile's first position; a dense run (the bucket holds more than 1 / kDenseShare of the
// tile) lists nothing and is drawn by walking the whole tile, keeping the bucket's voxels. Dense runs
// keep the lists small where a few values dominate (air in a CT scan), which bounds GPU bytes per voxel.
struct SliceRun {
    uint32_t first = 0;      // sparse: first entry in AxisLists::entries()
    uint32_t count = 0;      // sparse: entries; dense: positions in the tile
    uint32_t voxels = 0;     // voxels of the bucket (== count when sparse)
    uint32_t slice = 0;      // coordinate along the axis
    uint32_t tileBase = 0;   // in-slice position of the tile's first voxel
    uint16_t bucket = 0;
    bool dense = false;
    // In-slice bounds of the bucket's voxels along the slice's two axes (a1, a2 below), inclusive:
    // what the slice's sheet must cover when this run is drawn.
    glm::u16vec2 lo{0}, hi{0};
};

// In-slice position of voxel v in a slice along `axis`: v[a1] + v[a2] * dims[a1], a1 = (axis+1)%3,
// a2 = (axis+2)%3 (the same in-plane axes as the classifier's patches).
struct AxisLists {
    // Read-only once built, and shared: copies of the scene (the editor's render thread) and a renderer
    // keeping the axes it does not draw share these, where each held a copy (a quarter of a large
    // volume's render memory).
    std::shared_ptr<const std::vector<uint16_t>> sharedEntries;
    const std::vector<uint16_t>& entries() const {
        static const std::vector<uint16_t> none;
        return sharedEntries ? *sharedEntries : none;
    }
    std::vector<SliceRun> runs;          // sorted by (slice, tile, bucket)
    std::vector<uint32_t> sliceRuns;     // runs of slice s: [sliceRuns[s], sliceRuns[s + 1])
};

// Gradient opacity baked for one scene: entry b is the TF's gradient factor at the magnitude the packed
// magnitude byte b stands for (binMagnitude, shading.h), kGradientBins entries. Indexed by the byte each
// voxel's packed gradient already holds, it costs no memory a voxel and a TF edit bakes 256 floats.
using GradientFactors = std::vector<float>;

// The 2D transfer function baked for one scene: RGBA per cell of (value, gradient magnitude), cell
// tf2dCell(class, magnitude byte): kTf2dValueBins over the window (16 consecutive classes each) by
// kTf2dGradientBins over the magnitude byte (4 consecutive bytes each). 16384 cells, so a cell index fits
// the 14 bits tiled splatting's records keep for a colour index (tile_record.comp) and a TF edit bakes
// and uploads 256 KiB. Entry (k, j) is evaluate2d at the middle of its classes' values and of its bytes'
// magnitudes on the byte's square-root axis.
constexpr int kTf2dValueBins = 256;
constexpr int kTf2dGradientBins = 64;
constexpr int kTf2dCells = kTf2dValueBins * kTf2dGradientBins;
constexpr int kTf2dClassShift = 4;      // kLutSize / kTf2dValueBins == 1 << 4
constexpr int kTf2dByteShift = 2;       // kGradientBins / kTf2dGradientBins == 1 << 2
static_assert(kLutSize >> kTf2dClassShift == kTf2dValueBins && kGradientBins >> kTf2dByteShift == kTf2dGradientBins);
inline int tf2dCell(uint16_t cls, int magnitudeByte) {
    return (cls >> kTf2dClassShift) * kTf2dGradientBins + (magnitudeByte >> kTf2dByteShift);
}
using Tf2dTable = std::vector<glm::vec4>;
// The table of tf's widgets over `window` and magnitudes up to gradientMax (kTf2dCells entries).
Tf2dTable bakeTf2d(const TransferFunction& tf, ValueRange window, double gradientMax);

struct SplatScene {
    std::string name;                    // the volume's name, for messages
    glm::ivec3 dims{0};
    glm::dvec3 spacing{1.0};
    glm::dvec3 origin{0.0};
    glm::dvec3 centre{0.0};
    double radius = 0.0;                 // bounding radius of the voxel centres
    glm::dmat3 axes{1.0};                // the volume's axes in its world frame, turned about centre by
                                         // the image plane (Volume::drawnAxes): oblique scans
    ValueRange window;                   // data values mapped to TF domain [0,1]
    std::vector<uint16_t> classes;       // per voxel, x fastest: index into lut
    Lut lut;
    std::array<AxisLists, 3> lists;      // per axis (0 = x, 1 = y, 2 = z)
    size_t visibleVoxels = 0;            // voxels whose class has opacity > 0 under lut
    std::vector<uint32_t> classVoxels;   // per LUT class, its voxels: a TF edit counts the visible ones
                                         // from these kLutSize figures, not from every voxel
    std::vector<uint32_t> gradients;     // packed per voxel (shading.h), empty until addGradients
    double gradientMax = 0.0;            // their largest |g| (PackedGradients::maxMagnitude)
    TransferFunction tf;                 // what lut and gradientFactors were baked from (addGradients re-bakes)
    // Empty (a factor of 1) when the TF has no gradient opacity or the scene no gradients yet: the editor
    // shows a TF's gradient opacity once the gradients are computed, as it does shading. Non-empty only
    // with a gradient a voxel (opacityOf reads them): setTransferFunction and addGradients keep it so.
    GradientFactors gradientFactors;
    // Voxels per (class, magnitude byte), kLutSize x kGradientBins, built by the first TF with gradient
    // opacity (4 MiB): a class none of whose voxels gets a factor above 0 is then hidden (its LUT
    // opacity 0, culled by bucket), and visibleVoxels stays exact.
    std::vector<uint32_t> classGradientVoxels;
    // The 2D TF (bakeTf2d): empty unless the TF has widgets and the scene gradients, as gradientFactors.
    // When set it gives each voxel's colour and opacity; the LUT's opacity then only says whether any
    // voxel of the class is visible (its largest cell opacity), for the culling by bucket.
    Tf2dTable tf2d;

    size_t visibleCount() const { return visibleVoxels; }
    // A voxel's opacity: its 2D TF cell's, or its class's LUT opacity times its gradient factor, in float
    // as the GL computes it (splat_footprint.glsl). The oracle, the near layer and the truth all read it;
    // 0 culls the voxel.
    float opacityOf(uint32_t voxel) const {
        if (!tf2d.empty()) return tf2d[size_t(tf2dCell(classes[voxel], magnitudeBin(gradients[voxel])))].a;
        const float a = lut[classes[voxel]].a;
        return gradientFactors.empty() ? a : a * gradientFactors[size_t(magnitudeBin(gradients[voxel]))];
    }
    // A voxel's unshaded colour: its 2D TF cell's, or its class's LUT colour.
    glm::dvec3 colourOf(uint32_t voxel) const {
        if (!tf2d.empty()) return glm::dvec3(tf2d[size_t(tf2dCell(classes[voxel], magnitudeBin(gradients[voxel])))]);
        return glm::dvec3(lut[classes[voxel]]);
    }
    glm::dvec3 positionOf(uint32_t index) const;
    // Linear voxel index of in-slice position `pos` of `slice` along `axis`.
    uint32_t voxelAt(int axis, uint32_t slice, uint32_t pos) const;
};

// Classifies every voxel over `window` (the volume's range when lo == hi) and builds the lists.
SplatScene buildSplatScene(const Volume& volume, const TransferFunction& tf, ValueRange window = {});
// Packs the volume's gradients into the scene, for shading, surface splats and gradient opacity
// (GradientField from computeGradients, which reports progress and can be cancelled), and re-bakes the
// scene's TF with them.
void addGradients(SplatScene& scene, const GradientField& field);
// Packed already (the editor's worker); none (no texels) leaves the scene without gradients.
void addGradients(SplatScene& scene, PackedGradients packed);
// A TF edit: re-bakes the LUT, the gradient factors or the 2D table and recounts visible voxels; the lists stay.
void setTransferFunction(SplatScene& scene, const TransferFunction& tf);
// What a TF edit changes and a renderer uploads (SplatRenderer::setLut).
struct TfTables {
    Lut lut;
    GradientFactors gradientFactors;
    Tf2dTable tf2d;
};
inline TfTables tfTables(const SplatScene& scene) { return {scene.lut, scene.gradientFactors, scene.tf2d}; }
// Voxels per 2D TF cell (kTf2dCells, tf2dCell's order): the 2D section's histogram. Empty without gradients.
std::vector<uint32_t> valueGradientHistogram(const SplatScene& scene);
// The data values of the voxels the LUT draws (opacity > 0): from the lowest such class's lower edge to
// the highest's upper edge, over the scene's window. {0, 0} when none is drawn.
ValueRange visibleValueRange(const SplatScene& scene);

// Buckets holding at least one class with opacity > 0: the only ones drawn.
std::array<bool, kBuckets> activeBuckets(const Lut& lut);

// Points whose convex hull holds every voxel centre the LUT can show, grown by `reach` (object units per
// axis): the corners of each slice along x's box around its active buckets' bounds (SliceRun::lo, hi).
// Bucket by bucket, so the hull can hold transparent voxels of a bucket with visible classes. The grid's
// corners when nothing is visible.
std::vector<glm::dvec3> visibleOutline(const SplatScene& scene, glm::dvec3 reach = glm::dvec3(0.0));

// How much of each half size of the image a framed view leaves free around what it frames.
constexpr double kFrameMargin = 0.05;
// frameView() of visibleOutline(), grown by the kernels' cutoff: the view along `camera`'s line of sight
// that shows everything visible, as large as a width x height image allows.
Camera framedCamera(const Camera& camera, const SplatScene& scene, const SplatSettings& settings, int width, int height,
                    double minDistance = 0.0, double maxDistance = std::numeric_limits<double>::infinity());

// Splat-every-sample draws along the object axis most parallel to the view, far slices first.
struct Traversal {
    int axis = 2;
    bool descending = false;   // true: slices from the highest coordinate down
};
Traversal chooseTraversal(const ImagePlane& plane);

// The draw order: slices in traversal order (reversed when `reverse`, for front-to-back), within a
// slice its runs in order, within a run its voxels in order. Lists every voxel of the active buckets
// (allBuckets: of every bucket), transparent ones included: the renderers cull those per voxel.
// sliceStarts (optional) gets where each slice begins, plus the end.
std::vector<uint32_t> drawOrder(const SplatScene& scene, Traversal trav, bool reverse = false,
                                bool allBuckets = false, std::vector<uint32_t>* sliceStarts = nullptr);

} // namespace renderer
