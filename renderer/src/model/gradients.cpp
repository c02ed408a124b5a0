// Gradients by central differences over z-slabs with oneTBB (see gradients.h).
#include "renderer/model/gradients.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace renderer {
namespace {

// One component along `axis` at (x, y, z): central inside, one-sided on the faces. `values` are v's, as
// stored (VoxelValues::visit), so the inner loop reads them without a dispatch a voxel.
template <class Values>
double derivative(const Volume& v, const Values& values, int x, int y, int z, int axis) {
    const glm::ivec3 p(x, y, z);
    const int n = v.dims[axis];
    if (n < 2) return 0.0;
    glm::ivec3 lo = p, hi = p;
    lo[axis] = std::max(p[axis] - 1, 0);
    hi[axis] = std::min(p[axis] + 1, n - 1);
    const double d = double(values[v.index(hi.x, hi.y, hi.z)]) - double(values[v.index(lo.x, lo.y, lo.z)]);
    if (!std::isfinite(d)) return 0.0;
    return d / (double(hi[axis] - lo[axis]) * v.spacing[axis]);
}

template <class Values>
glm::dvec3 gradientAt(const Volume& v, const Values& values, int x, int y, int z) {
    return {derivative(v, values, x, y, z, 0), derivative(v, values, x, y, z, 1), derivative(v, values, x, y, z, 2)};
}

// Runs body(z) for every slice in batches, reporting progress between batches (on this thread).
// Returns false when cancelled. `from`..`to` is the share of the total progress this pass covers.
template <class Body>
bool forSlices(int depth, double from, double to, const ProgressCallback& progress, Body&& body) {
    const int batch = std::max(1, depth / 32);
    for (int z0 = 0; z0 < depth; z0 += batch) {
        const int z1 = std::min(depth, z0 + batch);
        tbb::parallel_for(tbb::blocked_range<int>(z0, z1), [&](const tbb::blocked_range<int>& r) {
            for (int z = r.begin(); z != r.end(); ++z)
                body(z);
        });
        if (progress && !progress(from + (to - from) * double(z1) / double(depth))) return false;
    }
    return true;
}

} // namespace

namespace {
template <class Values>
std::optional<GradientField> gradientsOf(const Volume& volume, const Values& values, const ProgressCallback& progress) {
    GradientField field;
    field.dims = volume.dims;
    if (volume.voxelCount() == 0 || volume.values.size() != volume.voxelCount()) return field;
    if (progress && !progress(0.0)) return std::nullopt;

    // 1. The largest |component|, which sets the quantisation scale.
    tbb::combinable<double> largest([] { return 0.0; });
    const glm::ivec3 d = volume.dims;
    if (!forSlices(d.z, 0.0, 0.5, progress, [&](int z) {
            double& m = largest.local();
            for (int y = 0; y < d.y; ++y)
                for (int x = 0; x < d.x; ++x) {
                    const glm::dvec3 g = glm::abs(gradientAt(volume, values, x, y, z));
                    m = std::max(m, std::max(g.x, std::max(g.y, g.z)));
                }
        }))
        return std::nullopt;
    field.scale = largest.combine([](double a, double b) { return std::max(a, b); });

    // 2. Quantise: q = round(g / scale * 32767), so |q| <= 32767.
    field.xyz.assign(volume.voxelCount() * 3, 0);
    const double k = field.scale > 0 ? 32767.0 / field.scale : 0.0;
    if (!forSlices(d.z, 0.5, 1.0, progress, [&](int z) {
            for (int y = 0; y < d.y; ++y)
                for (int x = 0; x < d.x; ++x) {
                    const glm::dvec3 g = gradientAt(volume, values, x, y, z);
                    const size_t i = volume.index(x, y, z) * 3;
                    for (int c = 0; c < 3; ++c)
                        field.xyz[i + size_t(c)] = int16_t(std::lround(g[c] * k));
                }
        }))
        return std::nullopt;
    return field;
}

} // namespace

std::optional<GradientField> computeGradients(const Volume& volume, const ProgressCallback& progress) {
    return volume.values.visit([&](const auto& values) { return gradientsOf(volume, values, progress); });
}

GradientStats gradientMagnitudeStats(const GradientField& field) {
    GradientStats s;
    const size_t n = field.xyz.size() / 3;
    if (n == 0) return s;
    std::vector<float> magnitudes(n);
    tbb::parallel_for(size_t(0), n, [&](size_t i) { magnitudes[i] = float(field.magnitude(i)); });
    double sum = 0;
    s.min = magnitudes[0];
    for (float m : magnitudes) {
        sum += m;
        s.min = std::min(s.min, double(m));
        s.max = std::max(s.max, double(m));
    }
    s.mean = sum / double(n);
    const size_t rank = size_t(std::llround(0.99 * double(n - 1)));
    std::nth_element(magnitudes.begin(), magnitudes.begin() + std::ptrdiff_t(rank), magnitudes.end());
    s.p99 = magnitudes[rank];
    return s;
}

} // namespace renderer
