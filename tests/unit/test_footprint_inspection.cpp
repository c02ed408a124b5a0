// The footprint inspector's figures (renderer/oracle/footprint_inspection.h): the ellipses at the cutoff
// equal the footprint's closed form, and the filter it reports is the one the classifier gives the patch.
#include "renderer/oracle/footprint_inspection.h"
#include "renderer/model/procedural.h"
#include "renderer/model/transfer_function.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace renderer;

namespace {

const TransferFunction kRamp = fromSharedPoints("ramp", {{0.0, {1, 1, 1}, 0.0}, {1.0, {1, 1, 1}, 1.0}});

} // namespace

TEST(FootprintInspection, AnEllipsesAxesAreItsVariancesEigenvaluesTimesTheCutoff) {
    // Axes 4 and 1 px turned 30 degrees: V = R diag(16, 1) R^T.
    const double a = std::numbers::pi / 6.0, c = std::cos(a), s = std::sin(a);
    const glm::dmat2 r(c, s, -s, c), v = r * glm::dmat2(16.0, 0.0, 0.0, 1.0) * glm::transpose(r);
    const Ellipse e = ellipseOf(v, 3.0);
    EXPECT_NEAR(e.semiAxesPx.x, 12.0, 1e-12);
    EXPECT_NEAR(e.semiAxesPx.y, 3.0, 1e-12);
    EXPECT_NEAR(e.angleRad, a, 1e-12);
}

// Orthographic, spacing 1, kernel scale 0.7: the projected kernel is a circle of sigma 0.7 fPx pixels, the
// low-pass one of 1 px, EWA their sum; at 3 sigmas the radii are 3 x those.
TEST(FootprintInspection, OrthographicRadiiAreTheKernelsSigmaInPixelsAndItsSumWithTheLowPass) {
    const Volume volume = makeMarschnerLobb(16);
    const SplatScene scene = buildSplatScene(volume, kRamp);
    Camera camera;
    camera.orthographic = true;
    const ImagePlane plane = makeImagePlane(camera, scene.centre, scene.radius, 64, 48);
    SplatSettings settings;
    settings.filter = FilterMode::Ewa;
    const auto f = inspectFootprint(scene, plane, settings, {3, 5, 7});
    ASSERT_TRUE(f.has_value());
    const double sigmaPx = settings.kernelScale * plane.fPx;
    const Ellipse rec = ellipseOf(f->reconstruction, f->cutoffSigmas), low = ellipseOf(f->lowPass, f->cutoffSigmas),
                  ewa = ellipseOf(f->ewa, f->cutoffSigmas);
    EXPECT_NEAR(rec.semiAxesPx.x, 3.0 * sigmaPx, 1e-9);
    EXPECT_NEAR(rec.semiAxesPx.y, 3.0 * sigmaPx, 1e-9);
    EXPECT_NEAR(low.semiAxesPx.x, 3.0, 1e-12);
    EXPECT_NEAR(ewa.semiAxesPx.y, 3.0 * std::sqrt(sigmaPx * sigmaPx + 1.0), 1e-9);
    EXPECT_NEAR(f->kernelPx.x, sigmaPx, 1e-9);
    EXPECT_NEAR(f->centrePx.x, plane.centrePx.x + (plane.toCamera(scene.positionOf(scene.dims.x * (5 + 7 * 16) + 3)).x *
                                                   plane.fPx), 1e-9);
    EXPECT_EQ(f->patchFilter, FilterMode::Ewa) << "not adaptive: the filter set";
}

// Adaptive: near voxels of a close view take reconstruction, far ones of a distant view low-pass, each as
// classifyPatch says for its patch; a kernel reaching the near plane has no splat to inspect.
TEST(FootprintInspection, AdaptiveReportsThePatchsFilterAndNothingAtTheEye) {
    const Volume volume = makeMarschnerLobb(16);
    const SplatScene scene = buildSplatScene(volume, kRamp);
    SplatSettings settings;
    settings.filter = FilterMode::Adaptive;
    for (const double distance : {1.2, 40.0}) {
        const Camera camera{30, 20, distance, 30.0};
        const ImagePlane plane = makeImagePlane(camera, scene.centre, scene.radius, 160, 120);
        const auto f = inspectFootprint(scene, plane, settings, {8, 8, 8});
        ASSERT_TRUE(f.has_value());
        const FilterMode expected = classifyPatch(scene, plane, adaptiveThresholds(scene.spacing, plane, settings),
                                                  settings.patchSize, chooseTraversal(plane).axis,
                                                  uint32_t((8 * 16 + 8) * 16 + 8));
        EXPECT_EQ(f->patchFilter, expected);
        EXPECT_EQ(f->patchFilter, distance < 2.0 ? FilterMode::Reconstruction : FilterMode::LowPass)
            << "at distance " << distance << " R_k is " << f->kernelPx.x << " px";
    }
    const ImagePlane inside = makeImagePlane(Camera{30, 20, 0.05, 60.0}, scene.centre, scene.radius, 64, 64);
    EXPECT_FALSE(inspectFootprint(scene, inside, settings, {8, 8, 8}).has_value())
        << "the centre voxel's kernel holds the eye";
}
