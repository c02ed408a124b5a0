// Gradients (central differences in object units, quantised, parallel, cancellable) and the window
// choices (data range, percentiles, custom) that map data values onto the transfer function.
#include "renderer/errors.h"
#include "renderer/model/gradients.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/window.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>

using namespace renderer;

namespace {

// v = 2x + 3y - z in object units, on a grid with spacing (0.5, 2, 1): grad v = (2, 3, -1) everywhere.
Volume linearRamp() {
    Volume v;
    v.name = "ramp";
    v.dims = {9, 7, 5};
    v.spacing = {0.5, 2.0, 1.0};
    v.type = VoxelType::F32;
    v.values.floats().resize(v.voxelCount());
    for (int z = 0; z < v.dims.z; ++z)
        for (int y = 0; y < v.dims.y; ++y)
            for (int x = 0; x < v.dims.x; ++x) {
                const glm::dvec3 p = v.positionOf(x, y, z);
                v.values.floats()[v.index(x, y, z)] = float(2 * p.x + 3 * p.y - p.z);
            }
    updateRange(v);
    return v;
}

TEST(Gradients, LinearRampGivesItsSlopeInObjectUnitsEverywhereIncludingFaces) {
    const Volume v = linearRamp();
    const auto field = computeGradients(v);
    ASSERT_TRUE(field);
    EXPECT_EQ(field->dims, v.dims);
    EXPECT_DOUBLE_EQ(field->scale, 3.0); // the largest component
    const double quantum = field->scale / 32767.0;
    for (size_t i = 0; i < v.voxelCount(); ++i) {
        const glm::dvec3 g = field->at(i);
        ASSERT_NEAR(g.x, 2.0, quantum) << "voxel " << i;
        ASSERT_NEAR(g.y, 3.0, quantum) << "voxel " << i;
        ASSERT_NEAR(g.z, -1.0, quantum) << "voxel " << i;
    }
    const GradientStats s = gradientMagnitudeStats(*field);
    EXPECT_NEAR(s.mean, std::sqrt(14.0), 1e-3);
    EXPECT_NEAR(s.max, std::sqrt(14.0), 1e-3);
}

TEST(Gradients, ResultDoesNotDependOnTheThreadCount) {
    const Volume v = linearRamp();
    std::vector<int16_t> single;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        single = computeGradients(v)->xyz;
    }
    EXPECT_EQ(computeGradients(v)->xyz, single);
}

TEST(Gradients, ProgressRisesToOneAndFalseCancels) {
    const Volume v = linearRamp();
    std::vector<double> seen;
    ASSERT_TRUE(computeGradients(v, [&](double f) {
        seen.push_back(f);
        return true;
    }));
    ASSERT_GE(seen.size(), 3u);
    EXPECT_EQ(seen.front(), 0.0);
    EXPECT_EQ(seen.back(), 1.0);
    for (size_t i = 1; i < seen.size(); ++i)
        EXPECT_GE(seen[i], seen[i - 1]);

    int calls = 0;
    EXPECT_FALSE(computeGradients(v, [&](double) { return ++calls < 2; }));
    EXPECT_EQ(calls, 2); // stopped at the first check after the refusal
}

TEST(Gradients, NonFiniteNeighboursAndSingleVoxelAxesGiveZeroComponents) {
    Volume v;
    v.dims = {3, 1, 1};
    v.values = {0.0f, std::numeric_limits<float>::quiet_NaN(), 4.0f};
    updateRange(v);
    const auto field = computeGradients(v);
    ASSERT_TRUE(field);
    // Voxels 0 and 2 difference against the NaN: 0. Voxel 1's central difference skips itself: (4 - 0) / 2.
    EXPECT_EQ(field->at(0), glm::dvec3(0.0));
    EXPECT_EQ(field->at(2), glm::dvec3(0.0));
    EXPECT_EQ(field->at(1), glm::dvec3(2.0, 0.0, 0.0));
}

TEST(Window, PercentilesAreNearestRankValuesOfTheFiniteVoxels) {
    Volume v;
    v.dims = {102, 1, 1};
    for (int i = 0; i < 100; ++i)
        v.values.floats().push_back(float(i * 10 - 1000)); // -1000 .. -10, HU-like
    v.values.floats().push_back(std::numeric_limits<float>::quiet_NaN());
    v.values.floats().push_back(std::numeric_limits<float>::infinity());
    updateRange(v);
    const ValueRange p = percentileWindow(v, 1.0, 99.0);
    EXPECT_EQ(p.lo, -990.0f); // rank round(0.01 * 99) = 1
    EXPECT_EQ(p.hi, -20.0f);  // rank round(0.99 * 99) = 98
    EXPECT_EQ(percentileWindow(v, 0, 100).lo, v.range.lo);
    EXPECT_EQ(percentileWindow(v, 0, 100).hi, v.range.hi);
    EXPECT_THROW(percentileWindow(v, 50, 10), RenderError);
    EXPECT_THROW(percentileWindow(v, -1, 10), RenderError);

    EXPECT_EQ(windowFor(v, {}).lo, v.range.lo);
    EXPECT_EQ(windowFor(v, {.mode = WindowMode::Percentile, .custom = {}}).hi, -20.0f);
    EXPECT_EQ(windowFor(v, {.mode = WindowMode::Custom, .custom = {-500, -100}}).lo, -500.0f);
    EXPECT_THROW(windowFor(v, {.mode = WindowMode::Custom, .custom = {5, 5}}), RenderError);
    EXPECT_STREQ(windowModeName(WindowMode::Percentile), "percentile 1-99");
}

TEST(Window, SceneClassifiesOverTheWindowItIsGiven) {
    Volume v;
    v.dims = {3, 1, 1};
    v.values = {-1000, 0, 1000};
    updateRange(v);
    const TransferFunction tf = builtinPreset("grey-ramp");
    const SplatScene full = buildSplatScene(v, tf);
    const SplatScene narrow = buildSplatScene(v, tf, {-10, 10});
    EXPECT_EQ(full.window.lo, -1000.0f);
    EXPECT_EQ(narrow.window.hi, 10.0f);
    EXPECT_LT(full.classes[1], narrow.classes[2]); // 1000 saturates the narrow window's top
    EXPECT_EQ(narrow.classes[0], full.classes[0]); // both bottom out at the lowest class
}

} // namespace
