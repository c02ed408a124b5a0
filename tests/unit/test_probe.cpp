// probePixel: the voxel a pixel shows, found by marching its ray through the classified grid.
#include "renderer/oracle/probe.h"
#include "renderer/model/transfer_function.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace renderer;

namespace {

// 32^3 voxels: 100 inside a ball of radius 8 voxels about the centre, 0 elsewhere.
Volume ball() {
    Volume v;
    v.name = "ball";
    v.dims = {32, 32, 32};
    v.values.floats().resize(v.voxelCount());
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x)
                v.values.floats()[v.index(x, y, z)] = glm::length(glm::dvec3(x, y, z) - v.centre()) <= 8.0 ? 100.0f : 0.0f;
    v.range = {0.0f, 100.0f};
    return v;
}

const TransferFunction kRamp = fromSharedPoints("ramp", {{0.0, {1, 1, 1}, 0.0}, {1.0, {1, 1, 1}, 1.0}});

} // namespace

TEST(PixelProbe, TheCentrePixelFindsTheBallsFrontSurfaceAndAPixelBesideItNothing) {
    const Volume volume = ball();
    const SplatScene scene = buildSplatScene(volume, kRamp);
    for (const bool ortho : {false, true}) {
        Camera camera;
        camera.orthographic = ortho;
        const ImagePlane plane = makeImagePlane(camera, scene.centre, scene.radius, 64, 64);
        const auto hit = probePixel(scene, SplatSettings{}, plane, {32.0, 32.0});
        ASSERT_TRUE(hit.has_value()) << (ortho ? "orthographic" : "perspective");
        EXPECT_EQ(volume.at(hit->voxel.x, hit->voxel.y, hit->voxel.z), 100.0f);
        EXPECT_GE(hit->alpha, 0.5);
        // Opacity 1 a voxel length: 1 - exp(-0.5) a half-voxel step, so the second step inside reaches 0.5.
        const double front = plane.toCamera(scene.centre).z - 8.0;
        EXPECT_NEAR(hit->depth, front + 1.0, 1.0) << (ortho ? "orthographic" : "perspective");
        // The voxel lies on the pixel's ray: it projects back onto the pixel, within a voxel's size there.
        const double voxelPx = ortho ? plane.fPx : plane.fPx / hit->depth;
        const glm::dvec2 back = plane.project(plane.toCamera(volume.positionOf(hit->voxel.x, hit->voxel.y, hit->voxel.z)));
        EXPECT_LE(glm::length(back - glm::dvec2(32.0, 32.0)), voxelPx);
        EXPECT_FALSE(probePixel(scene, SplatSettings{}, plane, {1.0, 1.0}).has_value()) << "a corner sees only air";
    }
}

TEST(PixelProbe, AFainterTfOrThinnerDensityReachesTheThresholdDeeperOrNotAtAll) {
    const Volume volume = ball();
    SplatScene scene = buildSplatScene(volume, kRamp);
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, 64, 64);
    SplatSettings settings;
    const auto dense = probePixel(scene, settings, plane, {32.0, 32.0});
    settings.density = 0.1;   // optical depth 0.1 a voxel: 0.5 needs about 7 voxels of the ball
    const auto thin = probePixel(scene, settings, plane, {32.0, 32.0});
    ASSERT_TRUE(dense && thin);
    EXPECT_NEAR(thin->depth - dense->depth, 6.0, 1.0);
    settings.density = 0.01;  // 16 voxels through the ball: alpha 0.15
    EXPECT_FALSE(probePixel(scene, settings, plane, {32.0, 32.0}).has_value());
    setTransferFunction(scene, fromSharedPoints("clear", {{0.0, {1, 1, 1}, 0.0}, {1.0, {1, 1, 1}, 0.0}}));
    EXPECT_FALSE(probePixel(scene, SplatSettings{}, plane, {32.0, 32.0}).has_value());
}
