// Levels of detail for far views: the pixel-size test with its hysteresis, the optical mass test that
// keeps thin features, and what the chosen level draws against the full volume (CPU oracle).
#include "renderer/math/camera.h"
#include "renderer/math/classifier.h"
#include "renderer/math/metrics.h"
#include "renderer/model/detail_levels.h"
#include "renderer/oracle/reference_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace renderer;

namespace {

// A ball whose value falls smoothly from 1 at the centre to 0 at `radius` voxels, in an n^3 grid.
Volume smoothBall(int n, double radius) {
    Volume v;
    v.name = "smooth-ball";
    v.dims = glm::ivec3(n);
    std::vector<float> values(size_t(n) * size_t(n) * size_t(n));
    const double c = 0.5 * (n - 1);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double r = std::sqrt((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c)) / radius;
                values[(size_t(z) * size_t(n) + size_t(y)) * size_t(n) + size_t(x)] = float(std::max(0.0, 1.0 - r * r));
            }
    v.values = std::move(values);
    v.range = {0.0f, 1.0f};
    return v;
}

// A one-voxel shell of value 1 at `radius` voxels from the centre, 0 elsewhere: a CT's skin.
Volume thinShell(int n, double radius) {
    Volume v = smoothBall(n, radius);
    v.name = "thin-shell";
    std::vector<float> values(v.voxelCount(), 0.0f);
    const double c = 0.5 * (n - 1);
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double r = std::sqrt((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c));
                if (std::abs(r - radius) < 0.5) values[(size_t(z) * size_t(n) + size_t(y)) * size_t(n) + size_t(x)] = 1.0f;
            }
    v.values = std::move(values);
    return v;
}

// Opacity rising linearly with the value: averaging values averages opacities.
TransferFunction ramp() { return fromSharedPoints("ramp", {{0.0, {1, 0.5, 0.2}, 0.0}, {1.0, {1, 0.5, 0.2}, 0.8}}); }
// Opaque only near 1: a mean of a shell voxel and air falls outside the band.
TransferFunction band() {
    return fromSharedPoints("band", {{0.0, {1, 1, 1}, 0.0}, {0.85, {1, 1, 1}, 0.0}, {0.9, {1, 1, 1}, 0.9}, {1.0, {1, 1, 1}, 0.9}});
}

// Settings whose largest kernel at `level` spans `ratio` times the low-pass threshold in an orthographic view.
SplatSettings kernelsAtRatio(const ImagePlane& plane, glm::dvec3 spacing, int level, double ratio) {
    SplatSettings s;
    const double px = levelKernelPx(glm::ivec3(16), glm::dvec3(0.0), spacing, plane, s, level);
    s.kernelScale *= ratio * adaptiveThresholds(spacing, plane, s).lowPassBelowPx / px;
    return s;
}

} // namespace

TEST(DetailLevels, KernelPixelsAreTheLevelsSigmaAtTheNearestVoxel) {
    const glm::dvec3 spacing(1.0, 2.0, 1.5);
    const ImagePlane ortho = makeImagePlane(Camera{.orthographic = true}, glm::dvec3(8.0), 20.0, 64, 64);
    const SplatSettings s;
    for (int k = 0; k <= 2; ++k)
        EXPECT_NEAR(levelKernelPx(glm::ivec3(16), glm::dvec3(0.0), spacing, ortho, s, k),
                    s.kernelScale * 2.0 * std::ldexp(1.0, k) * ortho.fPx, 1e-12);
    const ImagePlane persp = makeImagePlane(Camera{.distance = 5.0}, glm::dvec3(8.0), 20.0, 64, 64);
    const double nearest = persp.depthRange(glm::ivec3(16), glm::dvec3(0.0), spacing).x;
    EXPECT_NEAR(levelKernelPx(glm::ivec3(16), glm::dvec3(0.0), spacing, persp, s, 1),
                s.kernelScale * 2.0 * 2.0 * persp.fPx / nearest, 1e-12);
    // A camera inside the volume: no level is small enough.
    const ImagePlane inside = makeImagePlane(Camera{.distance = 0.2}, glm::dvec3(8.0), 20.0, 64, 64);
    EXPECT_TRUE(std::isinf(levelKernelPx(glm::ivec3(16), glm::dvec3(0.0), spacing, inside, s, 0)));
    EXPECT_EQ(coarsestLowPassLevel(glm::ivec3(16), glm::dvec3(0.0), spacing, inside, s, 3), 0);
}

TEST(DetailLevels, ALevelIsChosenOnlyWhereItsOwnKernelsTakeTheLowPassFilter) {
    const glm::dvec3 spacing(1.0);
    const ImagePlane plane = makeImagePlane(Camera{.orthographic = true}, glm::dvec3(8.0), 20.0, 64, 64);
    const auto level = [&](int at, double ratio, int previous = 0, double h = 0.0) {
        return coarsestLowPassLevel(glm::ivec3(16), glm::dvec3(0.0), spacing, plane, kernelsAtRatio(plane, spacing, at, ratio),
                                    3, previous, h);
    };
    EXPECT_EQ(level(1, 0.95), 1);   // level 1's kernels just under the threshold, level 2's twice that
    EXPECT_EQ(level(1, 1.05), 0);
    EXPECT_EQ(level(2, 0.95), 2);
    EXPECT_EQ(level(3, 0.5), 3);    // never past maxLevel
    // Hysteresis 0.2: entering level 1 needs its kernels under threshold / 1.2, leaving it over 1.2 x.
    EXPECT_EQ(level(1, 0.9, 0, 0.2), 0);
    EXPECT_EQ(level(1, 0.8, 0, 0.2), 1);
    EXPECT_EQ(level(1, 1.1, 1, 0.2), 1);
    EXPECT_EQ(level(1, 1.25, 1, 0.2), 0);
    EXPECT_EQ(level(2, 1.1, 1, 0.2), 1);   // level 1 kept, level 2 (coarser than last frame's) not entered
}

TEST(DetailLevels, HysteresisKeepsALevelWhileTheCameraWobblesAcrossTheThreshold) {
    const Volume volume = smoothBall(32, 14.0);
    const SplatScene scene = buildSplatScene(volume, ramp());
    const SplatSettings s;
    // The distance where level 1's kernels meet the threshold, then a wobble of 5 % about it.
    double lo = 1.5, hi = 200.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        const ImagePlane p = makeImagePlane(Camera{.distance = mid}, scene.centre, scene.radius, 128, 128);
        (coarsestLowPassLevel(scene.dims, scene.origin, scene.spacing, p, s, 1) == 1 ? hi : lo) = mid;
    }
    int previous = 0, switches = 0, withoutHysteresis = 0, last = 0;
    for (int frame = 0; frame < 40; ++frame) {
        const double distance = hi * (1.0 + 0.05 * std::sin(frame * 0.7));
        const ImagePlane p = makeImagePlane(Camera{.distance = distance}, scene.centre, scene.radius, 128, 128);
        const int level = coarsestLowPassLevel(scene.dims, scene.origin, scene.spacing, p, s, 1, previous, 0.2);
        switches += frame > 0 && level != previous;
        previous = level;
        const int bare = coarsestLowPassLevel(scene.dims, scene.origin, scene.spacing, p, s, 1);
        withoutHysteresis += frame > 0 && bare != last;
        last = bare;
    }
    EXPECT_GE(withoutHysteresis, 5);
    EXPECT_LE(switches, 1);
}

TEST(DetailLevels, OpticalMassIsKeptByAveragingASmoothFieldAndLostByAThinShell) {
    const Volume ball = smoothBall(32, 14.0);
    const SplatScene fineBall = buildSplatScene(ball, ramp());
    EXPECT_EQ(opticalMassChange(fineBall, fineBall), 0.0);
    const Volume coarseBall = halfResolution(ball, Downsample::Mean);
    // A linear TF over a smooth field: the mean's opacity is the opacities' mean, up to the LUT's bins.
    EXPECT_LT(opticalMassChange(fineBall, buildSplatScene(coarseBall, ramp(), fineBall.window)), 0.01);

    const Volume shell = thinShell(32, 12.0);
    const SplatScene fineShell = buildSplatScene(shell, band(), {0.0f, 1.0f});
    const SplatScene coarseShell = buildSplatScene(halfResolution(shell, Downsample::Mean), band(), {0.0f, 1.0f});
    EXPECT_GT(opticalMassChange(fineShell, coarseShell), 0.5);
    // Nothing visible in either: nothing changed. Visible only in the coarse one: all of it changed.
    const SplatScene empty = buildSplatScene(shell, fromSharedPoints("none", {{0.0, {1, 1, 1}, 0.0}, {1.0, {1, 1, 1}, 0.0}}));
    EXPECT_EQ(opticalMassChange(empty, empty), 0.0);
    EXPECT_EQ(opticalMassChange(empty, fineShell), 1.0);
}

TEST(DetailLevels, AFarViewDrawsACoarserLevelCloseToTheFullImageAndAThinShellStaysFull) {
    const Volume ball = smoothBall(32, 14.0);
    const SplatScene full = buildSplatScene(ball, ramp());
    SplatSettings s;
    s.density = 2.0;
    const ImagePlane nearPlane = makeImagePlane(Camera{.distance = 2.5}, full.centre, full.radius, 64, 64);
    const DetailLevel closeUp = chooseDetailLevel(ball, full, nearPlane, s);
    EXPECT_EQ(closeUp.level, 0);
    EXPECT_FALSE(closeUp.scene);

    // At 40 radii the ball is 6 px across a 64 px image, each fine kernel 0.08 px.
    const ImagePlane far = makeImagePlane(Camera{.distance = 40.0}, full.centre, full.radius, 64, 64);
    const DetailLevel d = chooseDetailLevel(ball, full, far, s);
    ASSERT_GE(d.level, 1);
    ASSERT_TRUE(d.scene);
    EXPECT_EQ(d.scene->dims, glm::ivec3(32 >> d.level));
    EXPECT_DOUBLE_EQ(d.densityScale, std::ldexp(1.0, d.level));
    EXPECT_LT(d.kernelPx, adaptiveThresholds(full.spacing, far, s).lowPassBelowPx);
    EXPECT_GT(d.massChange, 0.0);
    EXPECT_LE(d.massChange, kMaxMassChange);
    // Drawn from the full volume's view, with the level's density: within 1 % of full scale of the full frame.
    SplatSettings coarse = s;
    coarse.density *= d.densityScale;
    const Image fullImage = renderReference(full, far, s);
    const Image levelImage = renderReference(*d.scene, far, coarse);
    EXPECT_LT(compareImages(levelImage, fullImage).rmse, 0.01);

    const Volume shell = thinShell(32, 12.0);
    const SplatScene shellScene = buildSplatScene(shell, band(), {0.0f, 1.0f});
    const DetailLevel kept = chooseDetailLevel(shell, shellScene, far, s);
    EXPECT_GE(kept.pixelLevel, 1);
    EXPECT_EQ(kept.level, 0);
    EXPECT_EQ(kept.massChange, 0.0);
    EXPECT_GT(kept.refusedMassChange, kMaxMassChange);
}
