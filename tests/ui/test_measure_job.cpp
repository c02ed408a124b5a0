// The Filters panel's Measure job (app/editor_jobs.h): with Settings > Image-aligned slabs on it times the
// slabs in force after the sixteen filter x compositing settings, unless they cannot draw this scene.
#include "editor_jobs.h"
#include "test_paths.h"

#include "renderer/model/gradients.h"
#include "renderer/model/procedural.h"

#include <gtest/gtest.h>

#include <cstdlib>

using namespace renderer;

namespace {

// A Marschner-Lobb block, with gradient opacity in its TF when asked (then post-classification refuses it).
SplatScene measuredScene(bool gradientOpacity) {
    const Volume volume = makeMarschnerLobb(8);
    TransferFunction tf = fromSharedPoints("ramp", {{0.0, {0.1, 0.1, 0.1}, 0.3}, {1.0, {1.0, 1.0, 1.0}, 0.9}});
    if (gradientOpacity) tf.gradientOpacity = {{0.0, 0.0}, {1.0, 1.0}};
    SplatScene scene = buildSplatScene(volume, tf);
    addGradients(scene, *computeGradients(volume));
    return scene;
}

} // namespace

TEST(MeasureJob, TimesTheSlabsInForceLastUnlessTheyRefuseToPostClassifyTheScene) {
    // Its truths go to the test's own cache (the job starts computing them; leaving it cancels them).
    setenv("SPLATLAB_CACHE_DIR", testing_support::testOutputDir("measure_job_cache").c_str(), 1);
    SplatSettings settings;
    settings.compositing = Compositing::SheetFrontToBack;
    const auto jobFor = [&](bool gradientOpacity, bool postClassified) {
        const SplatScene scene = measuredScene(gradientOpacity);
        const ImagePlane view = makeImagePlane(Camera{}, scene.centre, scene.radius, 16, 12);
        return std::make_unique<FilterComparisonJob>(
            scene, view, settings, SlabOptions{.thickness = 0.5, .postClassified = postClassified});
    };
    const size_t sheets = speedErrorSettings(settings).size();
    const auto post = jobFor(false, true);
    ASSERT_TRUE(post->slabs);
    EXPECT_TRUE(post->slabs->postClassified);
    EXPECT_EQ(post->settingsToMeasure(), sheets + 1);
    // Gradient opacity: post-classified slabs draw no frame; pre-classified ones do.
    EXPECT_FALSE(jobFor(true, true)->slabs);
    EXPECT_EQ(jobFor(true, true)->settingsToMeasure(), sheets);
    EXPECT_TRUE(jobFor(true, false)->slabs);
    const auto none = std::make_unique<FilterComparisonJob>(measuredScene(false),
                                                            makeImagePlane(Camera{}, {4, 4, 4}, 8.0, 16, 12), settings,
                                                            std::nullopt);
    EXPECT_EQ(none->settingsToMeasure(), sheets);
}
