// Pre-classification: voxel classes, the LUT and the per-axis bucketed slice lists (see splat_scene.h).
#include "renderer/model/splat_scene.h"

#include "renderer/errors.h"
#include "renderer/math/shading.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace renderer {

glm::dvec3 SplatScene::positionOf(uint32_t index) const {
    const uint32_t x = index % uint32_t(dims.x);
    const uint32_t y = (index / uint32_t(dims.x)) % uint32_t(dims.y);
    const uint32_t z = index / (uint32_t(dims.x) * uint32_t(dims.y));
    return origin + spacing * glm::dvec3(x, y, z);
}

uint32_t SplatScene::voxelAt(int axis, uint32_t slice, uint32_t pos) const {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    glm::uvec3 v;
    v[axis] = slice;
    v[a1] = pos % uint32_t(dims[a1]);
    v[a2] = pos / uint32_t(dims[a1]);
    return (v.z * uint32_t(dims.y) + v.y) * uint32_t(dims.x) + v.x;
}

namespace {

// The classes of slices s0 .. s0 + n - 1 across `axis`, slice after slice, each in position order
// (voxelAt's). Read in memory order: a slice across x or y visited voxel by voxel strides through the
// volume, a cache line for each voxel (bonsai's scene took twice as long to build, renderer_bench
// window-edit).
void gatherSliceClasses(const SplatScene& s, int axis, uint32_t s0, uint32_t n, std::vector<uint16_t>& out) {
    const glm::ivec3 d = s.dims;
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const size_t sliceSize = size_t(d[a1]) * size_t(d[a2]);
    out.resize(n * sliceSize);
    glm::ivec3 lo(0), hi = d;
    lo[axis] = int(s0), hi[axis] = int(s0 + n);
    std::array<size_t, 3> step{};   // where one voxel along x, y, z moves in `out`
    step[size_t(axis)] = sliceSize, step[size_t(a1)] = 1, step[size_t(a2)] = size_t(d[a1]);
    for (int z = lo.z; z < hi.z; ++z)
        for (int y = lo.y; y < hi.y; ++y) {
            const uint16_t* row = &s.classes[(size_t(z) * size_t(d.y) + size_t(y)) * size_t(d.x)];
            size_t at = size_t(z - lo.z) * step[2] + size_t(y - lo.y) * step[1];
            for (int x = lo.x; x < hi.x; ++x, at += step[0]) out[at] = row[x];
        }
}

// One slice's runs and entries, from its classes in position order (rowLength positions a row): per
// tile, count the buckets, mark the dense ones, list the others' voxels.
// One slice's runs and entries while an axis is built.
struct SliceLists {
    std::vector<uint16_t> entries;
    std::vector<SliceRun> runs;
};

void buildSliceLists(const uint16_t* classes, uint32_t sliceSize, uint32_t rowLength, uint32_t slice, SliceLists& out) {
    for (uint32_t tileBase = 0; tileBase < sliceSize; tileBase += kTileVoxels) {
        const uint32_t tileSize = std::min(kTileVoxels, sliceSize - tileBase);
        std::array<uint32_t, kBuckets> count{};
        std::array<glm::u16vec2, kBuckets> lo, hi;
        lo.fill(glm::u16vec2(UINT16_MAX));
        hi.fill(glm::u16vec2(0));
        // By stretches of one bucket within a row: most of a scan is air, long stretches of one class.
        const uint16_t* tile = classes + tileBase;
        for (uint32_t p = 0; p < tileSize;) {
            const uint32_t x = (tileBase + p) % rowLength, y = (tileBase + p) / rowLength;
            const uint32_t rowEnd = std::min(tileSize, p + (rowLength - x));
            const int b = tile[p] >> kBucketShift;
            uint32_t q = p + 1;
            while (q < rowEnd && tile[q] >> kBucketShift == b) ++q;
            count[size_t(b)] += q - p;
            lo[size_t(b)] = glm::min(lo[size_t(b)], glm::u16vec2(x, y));
            hi[size_t(b)] = glm::max(hi[size_t(b)], glm::u16vec2(x + (q - p) - 1, y));
            p = q;
        }
        std::array<uint32_t, kBuckets> offset{};
        const uint32_t base = uint32_t(out.entries.size());
        uint32_t listed = 0;
        std::array<bool, kBuckets> dense{};
        for (int b = 0; b < kBuckets; ++b) {
            if (count[size_t(b)] == 0) continue;
            SliceRun r;
            r.slice = slice;
            r.tileBase = tileBase;
            r.bucket = uint16_t(b);
            r.dense = dense[size_t(b)] = kDenseShare * count[size_t(b)] > tileSize;
            r.first = r.dense ? 0 : base + listed;
            r.count = r.dense ? tileSize : count[size_t(b)];
            r.voxels = count[size_t(b)];
            r.lo = lo[size_t(b)];
            r.hi = hi[size_t(b)];
            offset[size_t(b)] = r.first;
            if (!r.dense) listed += count[size_t(b)];
            out.runs.push_back(r);
        }
        out.entries.resize(base + listed);
        for (uint32_t p = 0; p < tileSize; ++p) {
            const int b = classes[tileBase + p] >> kBucketShift;
            if (!dense[size_t(b)]) out.entries[offset[size_t(b)]++] = uint16_t(p);
        }
    }
}

// One axis: every slice's lists (buildSliceLists), concatenated.
AxisLists buildAxisLists(const SplatScene& s, int axis) {
    const glm::ivec3 d = s.dims;
    const uint32_t slices = uint32_t(d[axis]);
    const uint32_t sliceSize = uint32_t(d[(axis + 1) % 3]) * uint32_t(d[(axis + 2) % 3]);
    // Slices are independent: build blocks of them in parallel, then concatenate. A block gathers its
    // classes at once (up to 16 slices, at most 8 MB): across x, each row then gives 16 slices 32 bytes
    // of one cache line, where a slice alone would read a line for each of its voxels.
    const uint32_t block = std::clamp<uint32_t>((uint32_t(1) << 22) / std::max<uint32_t>(sliceSize, 1), 1, 16);
    std::vector<SliceLists> perSlice(slices);
    tbb::parallel_for(uint32_t(0), (slices + block - 1) / block, [&](uint32_t b) {
        const uint32_t s0 = b * block, n = std::min(block, slices - s0);
        // Slices across z lie in memory in position order already.
        std::vector<uint16_t> blockClasses;
        if (axis != 2) gatherSliceClasses(s, axis, s0, n, blockClasses);
        const uint16_t* classes = axis == 2 ? &s.classes[size_t(s0) * sliceSize] : blockClasses.data();
        for (uint32_t slice = s0; slice < s0 + n; ++slice)
            buildSliceLists(classes + size_t(slice - s0) * sliceSize, sliceSize, uint32_t(d[(axis + 1) % 3]), slice,
                            perSlice[slice]);
    });
    AxisLists lists;
    std::vector<uint16_t> entries;
    lists.sliceRuns.push_back(0);
    for (uint32_t slice = 0; slice < slices; ++slice) {
        const uint32_t shift = uint32_t(entries.size());
        for (SliceRun r : perSlice[slice].runs) {
            if (!r.dense) r.first += shift;
            lists.runs.push_back(r);
        }
        entries.insert(entries.end(), perSlice[slice].entries.begin(), perSlice[slice].entries.end());
        std::vector<uint16_t>().swap(perSlice[slice].entries);   // the slice's share is now in `entries`
        lists.sliceRuns.push_back(uint32_t(lists.runs.size()));
    }
    lists.sharedEntries = std::make_shared<const std::vector<uint16_t>>(std::move(entries));
    return lists;
}

} // namespace

namespace {
SplatScene buildSplatSceneOrThrow(const Volume& volume, const TransferFunction& tf, ValueRange window);
} // namespace

// An allocation that fails while classifying becomes an error naming the volume and what was being built,
// so the editor reports it and keeps the scene it had.
SplatScene buildSplatScene(const Volume& volume, const TransferFunction& tf, ValueRange window) {
    try {
        return buildSplatSceneOrThrow(volume, tf, window);
    } catch (const std::bad_alloc&) {
        throw RenderError("volume '" + volume.name + "': out of memory building the splat lists of its " +
                          std::to_string(volume.voxelCount()) + " voxels (the voxel classes and the three axes' lists)");
    }
}

namespace {
SplatScene buildSplatSceneOrThrow(const Volume& volume, const TransferFunction& tf, ValueRange window) {
    if (volume.voxelCount() == 0 || volume.values.size() != volume.voxelCount())
        throw RenderError("volume '" + volume.name + "' has no voxels");
    // The readers refuse such files; a volume built in code (a phantom, a resampling) meets it here.
    if (volume.voxelCount() > kMaxVoxels)
        throw RenderError("volume '" + volume.name + "' has more than " + std::to_string(kMaxVoxels) + " voxels");
    if (std::max({volume.dims.x, volume.dims.y, volume.dims.z}) > kMaxAxisVoxels)
        throw RenderError("volume '" + volume.name + "' is longer than " + std::to_string(kMaxAxisVoxels) +
                          " voxels along an axis");
    SplatScene s;
    s.name = volume.name;
    s.dims = volume.dims;
    s.spacing = volume.spacing;
    s.origin = volume.origin;
    s.centre = volume.centre();
    s.radius = volume.boundingRadius();
    s.axes = volume.drawnAxes();
    s.window = (window.hi > window.lo) ? window : volume.range;
    s.classes.resize(volume.voxelCount());
    tbb::combinable<std::vector<uint32_t>> histograms([] { return std::vector<uint32_t>(kLutSize, 0); });
    volume.values.visit([&](const auto& values) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, s.classes.size()), [&](const tbb::blocked_range<size_t>& r) {
            std::vector<uint32_t>& histogram = histograms.local();
            for (size_t i = r.begin(); i < r.end(); ++i)
                ++histogram[s.classes[i] = classOf(float(values[i]), s.window.lo, s.window.hi)];
        });
    });
    s.classVoxels.assign(kLutSize, 0);
    histograms.combine_each([&](const std::vector<uint32_t>& h) {
        for (int c = 0; c < kLutSize; ++c) s.classVoxels[size_t(c)] += h[size_t(c)];
    });
    for (int axis = 0; axis < 3; ++axis) s.lists[size_t(axis)] = buildAxisLists(s, axis);
    setTransferFunction(s, tf);
    return s;
}
} // namespace

void addGradients(SplatScene& s, const GradientField& field) {
    if (field.dims != s.dims)
        throw RenderError("gradients of a " + std::to_string(field.dims.x) + "x" + std::to_string(field.dims.y) + "x" +
                          std::to_string(field.dims.z) + " volume do not fit scene '" + s.name + "'");
    addGradients(s, packGradients(field));
}

void addGradients(SplatScene& s, PackedGradients packed) {
    if (!packed.texels.empty() && packed.texels.size() != s.classes.size())
        throw RenderError(std::to_string(packed.texels.size()) + " packed gradients do not fit scene '" + s.name +
                          "' of " + std::to_string(s.classes.size()) + " voxels");
    s.gradients = std::move(packed.texels);
    s.gradientMax = packed.maxMagnitude;
    s.classGradientVoxels.clear();   // of the gradients before
    if (!s.lut.empty()) setTransferFunction(s, s.tf);
}

namespace {
// Voxels per (class, magnitude byte): one pass over the voxels, in parallel.
std::vector<uint32_t> countClassGradients(const SplatScene& s) {
    const size_t bins = size_t(kLutSize) * kGradientBins;
    tbb::combinable<std::vector<uint32_t>> counts([bins] { return std::vector<uint32_t>(bins, 0); });
    tbb::parallel_for(tbb::blocked_range<size_t>(0, s.classes.size()), [&](const tbb::blocked_range<size_t>& r) {
        std::vector<uint32_t>& c = counts.local();
        for (size_t i = r.begin(); i < r.end(); ++i)
            ++c[size_t(s.classes[i]) * kGradientBins + size_t(magnitudeBin(s.gradients[i]))];
    });
    std::vector<uint32_t> total(bins, 0);
    counts.combine_each([&](const std::vector<uint32_t>& c) {
        for (size_t k = 0; k < bins; ++k) total[k] += c[k];
    });
    return total;
}
} // namespace

Tf2dTable bakeTf2d(const TransferFunction& tf, ValueRange window, double gradientMax) {
    Tf2dTable table(static_cast<size_t>(kTf2dCells));
    const double lo = window.lo, span = double(window.hi) - double(window.lo);
    for (int j = 0; j < kTf2dGradientBins; ++j) {
        // The middle of the cell's bytes on the byte's square-root axis (binMagnitude's).
        const double a = ((j << kTf2dByteShift) + 0.5 * ((1 << kTf2dByteShift) - 1)) / 255.0;
        const double magnitude = gradientMax * a * a;
        for (int k = 0; k < kTf2dValueBins; ++k)
            table[size_t(k * kTf2dGradientBins + j)] =
                glm::vec4(evaluate2d(tf, lo + (k + 0.5) / kTf2dValueBins * span, magnitude));
    }
    return table;
}

std::vector<uint32_t> valueGradientHistogram(const SplatScene& s) {
    if (s.gradients.size() != s.classes.size() || s.classes.empty()) return {};
    std::vector<uint32_t> counted;   // counted here only when no TF has needed them yet
    const std::vector<uint32_t>& perClass =
        s.classGradientVoxels.empty() ? (counted = countClassGradients(s)) : s.classGradientVoxels;
    std::vector<uint32_t> cells(size_t(kTf2dCells), 0);
    for (int c = 0; c < kLutSize; ++c)
        for (int b = 0; b < kGradientBins; ++b)
            cells[size_t(tf2dCell(uint16_t(c), b))] += perClass[size_t(c) * kGradientBins + size_t(b)];
    return cells;
}

namespace {
// The 2D TF: the table, then per class its voxels whose cell is visible; a class with none is hidden
// (LUT opacity 0: culled by bucket), one with some keeps its largest cell opacity.
void setTf2d(SplatScene& s, const TransferFunction& tf) {
    s.tf2d = bakeTf2d(tf, s.window, s.gradientMax);
    if (s.classGradientVoxels.empty()) s.classGradientVoxels = countClassGradients(s);
    for (int c = 0; c < kLutSize; ++c) {
        size_t visible = 0;
        float largest = 0.0f;
        const uint32_t* counts = &s.classGradientVoxels[size_t(c) * kGradientBins];
        for (int b = 0; b < kGradientBins; ++b) {
            const float a = s.tf2d[size_t(tf2dCell(uint16_t(c), b))].a;
            if (a > 0.0f && counts[b] > 0) visible += counts[b], largest = std::max(largest, a);
        }
        s.lut[size_t(c)].a = largest;
        s.visibleVoxels += visible;
    }
}
} // namespace

void setTransferFunction(SplatScene& s, const TransferFunction& tf) {
    s.tf = tf;
    s.lut = bakeLut(tf, s.window);
    s.gradientFactors.clear();
    s.tf2d.clear();
    s.visibleVoxels = 0;
    const bool hasGradients = s.gradients.size() == s.classes.size() && !s.classes.empty();
    if (!tf.widgets2d.empty() && hasGradients) return setTf2d(s, tf);
    if (tf.gradientOpacity.empty() || s.gradients.size() != s.classes.size() || s.classes.empty()) {
        for (size_t c = 0; c < s.classVoxels.size(); ++c) s.visibleVoxels += s.lut[c].a > 0.0f ? s.classVoxels[c] : 0;
        return;
    }
    // Gradient opacity: a factor per magnitude byte, then each class's voxels whose factor is above 0.
    s.gradientFactors.resize(kGradientBins);
    for (int b = 0; b < kGradientBins; ++b)
        s.gradientFactors[size_t(b)] = float(evaluateGradientOpacity(tf, binMagnitude(b, s.gradientMax)));
    if (s.classGradientVoxels.empty()) s.classGradientVoxels = countClassGradients(s);
    for (size_t c = 0; c < size_t(kLutSize); ++c) {
        if (!(s.lut[c].a > 0.0f)) continue;
        size_t visible = 0;
        const uint32_t* counts = &s.classGradientVoxels[c * kGradientBins];
        for (size_t b = 0; b < size_t(kGradientBins); ++b) visible += s.gradientFactors[b] > 0.0f ? counts[b] : 0;
        if (visible == 0) s.lut[c].a = 0.0f;   // hidden at every gradient its voxels have: culled by bucket
        s.visibleVoxels += visible;
    }
}

ValueRange visibleValueRange(const SplatScene& s) {
    int first = -1, last = -1;
    for (int c = 0; c < kLutSize && size_t(c) < s.classVoxels.size() && size_t(c) < s.lut.size(); ++c)
        if (s.classVoxels[size_t(c)] > 0 && s.lut[size_t(c)].a > 0.0f) {
            if (first < 0) first = c;
            last = c;
        }
    if (first < 0) return {};
    const double lo = s.window.lo, span = double(s.window.hi) - double(s.window.lo);
    return {float(lo + span * first / kLutSize), float(lo + span * (last + 1) / kLutSize)};
}

std::array<bool, kBuckets> activeBuckets(const Lut& lut) {
    std::array<bool, kBuckets> active{};
    for (size_t c = 0; c < lut.size(); ++c) active[c >> kBucketShift] = active[c >> kBucketShift] || lut[c].a > 0.0f;
    return active;
}

std::vector<glm::dvec3> visibleOutline(const SplatScene& scene, glm::dvec3 reach) {
    const std::array<bool, kBuckets> active = activeBuckets(scene.lut);
    std::vector<glm::dvec3> points;
    // The box lo..hi (voxel indices) grown by reach: its eight corners.
    const auto addBox = [&](glm::ivec3 lo, glm::ivec3 hi) {
        const glm::dvec3 a = scene.origin + scene.spacing * glm::dvec3(lo) - reach;
        const glm::dvec3 b = scene.origin + scene.spacing * glm::dvec3(hi) + reach;
        for (int c = 0; c < 8; ++c) points.emplace_back((c & 1) ? b.x : a.x, (c & 2) ? b.y : a.y, (c & 4) ? b.z : a.z);
    };
    const AxisLists& lists = scene.lists[0];   // slices along x; in-slice axes y, z
    for (int x = 0; x < scene.dims.x; ++x) {       // a box per slice: the union of its active buckets'
        glm::ivec2 lo(std::numeric_limits<int>::max()), hi(-1);
        for (uint32_t r = lists.sliceRuns[size_t(x)]; r < lists.sliceRuns[size_t(x) + 1]; ++r) {
            const SliceRun& run = lists.runs[r];
            if (!active[run.bucket] || run.voxels == 0) continue;
            lo = glm::min(lo, glm::ivec2(run.lo)), hi = glm::max(hi, glm::ivec2(run.hi));
        }
        if (hi.x >= 0) addBox({x, lo.x, lo.y}, {x, hi.x, hi.y});
    }
    if (points.empty()) addBox(glm::ivec3(0), scene.dims - 1);
    return points;
}

Camera framedCamera(const Camera& camera, const SplatScene& scene, const SplatSettings& settings, int width, int height,
                    double minDistance, double maxDistance) {
    const glm::dvec3 reach = settings.cutoffSigmas * settings.kernelScale * scene.spacing;
    return frameView(camera, scene.centre, scene.radius, visibleOutline(scene, reach), width, height, kFrameMargin,
                     minDistance, maxDistance, scene.axes);
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

std::vector<uint32_t> drawOrder(const SplatScene& scene, Traversal trav, bool reverse, bool allBuckets,
                                std::vector<uint32_t>* sliceStarts) {
    const AxisLists& lists = scene.lists[size_t(trav.axis)];
    std::array<bool, kBuckets> active = activeBuckets(scene.lut);
    if (allBuckets) active.fill(true);
    const uint32_t slices = uint32_t(scene.dims[trav.axis]);
    const bool descending = trav.descending != reverse;
    std::vector<uint32_t> order;
    if (sliceStarts) sliceStarts->clear();
    for (uint32_t k = 0; k < slices; ++k) {
        const uint32_t slice = descending ? slices - 1 - k : k;
        if (sliceStarts) sliceStarts->push_back(uint32_t(order.size()));
        for (uint32_t r = lists.sliceRuns[slice]; r < lists.sliceRuns[slice + 1]; ++r) {
            const SliceRun& run = lists.runs[r];
            if (!active[run.bucket]) continue;
            for (uint32_t i = 0; i < run.count; ++i) {
                const uint32_t pos = run.tileBase + (run.dense ? i : lists.entries()[run.first + i]);
                const uint32_t voxel = scene.voxelAt(trav.axis, slice, pos);
                if (run.dense && (scene.classes[voxel] >> kBucketShift) != run.bucket) continue;
                order.push_back(voxel);
            }
        }
    }
    if (sliceStarts) sliceStarts->push_back(uint32_t(order.size()));
    return order;
}

} // namespace renderer
