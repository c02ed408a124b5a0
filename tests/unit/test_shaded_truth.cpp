// The ground truth of shaded frames: each kernel's colour lit along the exact ray. Per-fragment and
// per-splat shading are approximations of it, and it must tell them apart from an unshaded frame.
#include "renderer/errors.h"
#include "renderer/math/metrics.h"
#include "renderer/model/gradients.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/reference_renderer.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace renderer;

namespace {

struct ShadedView {
    SplatScene scene;
    ImagePlane plane;
};

// Marschner-Lobb's ripples give gradients in every direction; a mostly opaque ramp shows them lit.
ShadedView shadedView() {
    const Volume volume = makeMarschnerLobb(16);
    const TransferFunction tf = fromSharedPoints("ramp", {{0.0, {0.9, 0.8, 0.7}, 0.0}, {0.4, {0.9, 0.8, 0.7}, 0.0},
                                                          {0.6, {1.0, 0.9, 0.8}, 0.8}, {1.0, {1.0, 1.0, 1.0}, 1.0}});
    ShadedView v{buildSplatScene(volume, tf), {}};
    addGradients(v.scene, *computeGradients(volume));
    v.plane = makeImagePlane(Camera{30, 20, 2.5, 30.0}, v.scene.centre, v.scene.radius, 32, 32);
    return v;
}

// Coarser than the default tolerance: three truths in a test (1e-4 moves them by under 1e-4).
const GroundTruthOptions kOptions{.tolerance = 1e-4};

double psnrAgainst(const Image& image, const Image& truth) { return compareImages(image, truth).psnrDb; }

} // namespace

TEST(ShadedGroundTruth, ShadingChangesTheTruthAndBothShadingModesFollowIt) {
    const ShadedView v = shadedView();
    SplatSettings flat;
    SplatSettings perFragment = flat, perSplat = flat;
    perFragment.shading = SplatSettings::Shading::PerFragment;
    perSplat.shading = SplatSettings::Shading::PerSplat;
    ASSERT_TRUE(hasGroundTruth(perFragment));

    const Image unshadedTruth = renderGroundTruth(v.scene, v.plane, flat, kOptions);
    const Image shadedTruth = renderGroundTruth(v.scene, v.plane, perFragment, kOptions);
    EXPECT_GT(compareImages(shadedTruth, unshadedTruth).rmse, 0.02) << "lighting must show in the truth";
    // One truth for both modes: they differ only in how they approximate the ray's direction.
    EXPECT_EQ(groundTruthKey(v.scene, v.plane, perSplat, {}), groundTruthKey(v.scene, v.plane, perFragment, {}));
    EXPECT_NE(groundTruthKey(v.scene, v.plane, flat, {}), groundTruthKey(v.scene, v.plane, perFragment, {}));

    const Image fragmentImage = renderReference(v.scene, v.plane, perFragment);
    const Image splatImage = renderReference(v.scene, v.plane, perSplat);
    const double fragmentDb = psnrAgainst(fragmentImage, shadedTruth), splatDb = psnrAgainst(splatImage, shadedTruth);
    const double unshadedDb = psnrAgainst(renderReference(v.scene, v.plane, flat), unshadedTruth);
    std::printf("[ shaded truth ] PSNR per-fragment %.2f dB, per-splat %.2f dB; unshaded frame vs its truth %.2f dB; "
                "per-fragment vs the unshaded truth %.2f dB\n",
                fragmentDb, splatDb, unshadedDb, psnrAgainst(fragmentImage, unshadedTruth));
    // Shaded frames are as close to their truth as unshaded ones to theirs (within 3 dB), and much
    // closer than to the unshaded truth: the truth measures the shading, not only the splatting.
    EXPECT_GT(fragmentDb, unshadedDb - 3.0);
    EXPECT_GT(splatDb, unshadedDb - 3.0);
    EXPECT_GT(fragmentDb, psnrAgainst(fragmentImage, unshadedTruth) + 6.0);
}

TEST(ShadedGroundTruth, NeedsGradientsAndRefusesSurfaceSplats) {
    ShadedView v = shadedView();
    SplatSettings s;
    s.surfaceFlatten = 4.0;
    EXPECT_FALSE(hasGroundTruth(s));
    EXPECT_THROW(renderGroundTruth(v.scene, v.plane, s), RenderError);
    s.surfaceFlatten = 1.0;
    s.shading = SplatSettings::Shading::PerSplat;
    v.scene.gradients.clear();
    EXPECT_THROW(renderGroundTruth(v.scene, v.plane, s), RenderError);
}
