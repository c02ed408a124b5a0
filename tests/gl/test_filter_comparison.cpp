// Each setting's cost beside its error (filter_comparison.h, speed_error.h): the crop shows the view's own
// pixels, the error is the metric of that crop against its ground truth (X-ray's its own), every filter x
// compositing mode is timed with repeats, and where the view minifies a fine pattern, reconstruction alone
// (no screen filter) is the one that aliases.
#include "gl_fixture.h"
#include "image_compare.h"
#include "test_paths.h"

#include "renderer/gl/image_slabs_gl.h"
#include "renderer/oracle/filter_comparison.h"
#include "renderer/oracle/image_slabs.h"
#include "renderer/oracle/speed_error.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/math/metrics.h"
#include "renderer/model/procedural.h"

#include <cstdio>

using namespace renderer;

namespace {

TransferFunction opaqueRamp() {
    return fromSharedPoints("ramp", {{0.0, {0.1, 0.1, 0.1}, 0.3}, {1.0, {1.0, 1.0, 1.0}, 0.9}});
}

// What the speed-against-error tests measure: a Marschner-Lobb block under an opaque ramp, a 32x24 view of
// it and that view's centre 10 x 10 px, at density 0.3.
struct MeasuredView {
    SplatScene scene = buildSplatScene(makeMarschnerLobb(12), opaqueRamp());
    ImagePlane view = makeImagePlane(Camera{}, scene.centre, scene.radius, 32, 24);
    ImagePlane crop = centreCrop(view, 10);
    SplatSettings settings = [] {
        SplatSettings s;
        s.density = 0.3;
        return s;
    }();
};

} // namespace

TEST_F(GlTest, ACentreCropRendersTheViewsOwnPixels) {
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(16), opaqueRamp());
    const ImagePlane view = makeImagePlane(Camera{}, scene.centre, scene.radius, 72, 60);
    const ImagePlane crop = centreCrop(view, 24);
    ASSERT_EQ(crop.width, 24);
    ASSERT_EQ(crop.height, 24);
    EXPECT_EQ(centreCrop(view, 500).width, 72) << "a crop larger than the view is the view";
    SplatRenderer gl;
    gl.setScene(scene);
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    gl.render(view, s);
    const Image whole = gl.readback();
    gl.render(crop, s);
    const Image part = gl.readback();
    Image expected(24, 24);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x)
            for (int c = 0; c < 4; ++c) expected.pixel(x, y)[c] = whole.pixel(x + (72 - 24) / 2, y + (60 - 24) / 2)[c];
    EXPECT_LT(compareImages(part, expected).maxAbs, 1e-5);
}

TEST_F(GlTest, EachFiltersErrorIsItsCropAgainstTheGroundTruthAndMinifiedReconstructionAliases) {
    // A 1-voxel checkerboard of thin emitting material far away: kernels of about 0.2 px. Without the
    // screen filter the pattern aliases; low-pass, EWA and adaptive keep it smooth. (Thin: opaque
    // material saturates EWA's blurred optical depth, docs/accuracy.md "Filtering each footprint".)
    const TransferFunction blackWhite = fromSharedPoints("bw", {{0.0, {0.0, 0.0, 0.0}, 1.0}, {1.0, {1.0, 1.0, 1.0}, 1.0}});
    const SplatScene scene = buildSplatScene(makeCheckerboard({24, 24, 24}, 1), blackWhite);
    Camera far;
    far.distance = 12.0;
    const ImagePlane view = makeImagePlane(far, scene.centre, scene.radius, 64, 64);
    const ImagePlane crop = centreCrop(view, 16);
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    s.density = 0.02;
    const Image truth = renderGroundTruth(scene, crop, s);
    SplatRenderer gl;
    gl.setScene(scene);
    std::map<FilterMode, double> rmse;
    for (FilterMode f : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa, FilterMode::Adaptive}) {
        SplatSettings withFilter = s;
        withFilter.filter = f;
        const FilterMeasurement m = measureSetting(gl, view, crop, truth, withFilter, 3);
        EXPECT_EQ(m.filter, f);
        EXPECT_EQ(m.compositing, s.compositing);
        EXPECT_EQ(m.frames, 3);
        EXPECT_GT(m.frameMs, 0.0);
        EXPECT_LE(m.p10Ms, m.frameMs);
        EXPECT_GE(m.p90Ms, m.frameMs);
        // The figure is the crop's own error, as metrics.h measures it (tiles sum a pixel's splats in
        // atomic order, so a second frame may differ in the last float bits: on an H200 the RMSE moved
        // by 1.3e-6 of itself, on llvmpipe by less than 1e-6).
        SplatSettings same = s;
        same.filter = f;
        gl.render(crop, same);
        const ImageError e = compareImages(gl.readback(), truth);
        EXPECT_NEAR(m.rmse, e.rmse, 1e-5 * e.rmse) << filterModeName(f);
        EXPECT_NEAR(m.psnrDb, e.psnrDb, 1e-4) << filterModeName(f);
        rmse[f] = m.rmse;
        std::printf("[ filters  ] %-14s rmse %.5f  psnr %.1f dB  %.2f ms\n", filterModeName(f), m.rmse, m.psnrDb, m.frameMs);
    }
    EXPECT_GT(rmse[FilterMode::Reconstruction], 2.0 * rmse[FilterMode::Ewa]);
    EXPECT_GT(rmse[FilterMode::Reconstruction], 2.0 * rmse[FilterMode::LowPass]);
    EXPECT_LE(rmse[FilterMode::Adaptive], rmse[FilterMode::Ewa] * 1.5);
}

TEST_F(GlTest, SpeedAgainstErrorTimesEverySettingWithRepeatsAndTakesEachErrorAgainstItsOwnTruth) {
    // 16 settings, each timed `repeats` times, in speedErrorSettings' order; X-ray against X-ray's truth,
    // the others against the attenuating one.
    const MeasuredView measured;
    const auto& [scene, view, crop, base] = measured;
    const std::filesystem::path cache = testing_support::testOutputDir("speed_error_cache");
    const CropTruths truths = cropTruths(scene, crop, base, {}, cache);
    SplatSettings xray = base;
    xray.compositing = Compositing::XRay;
    EXPECT_LT(compareImages(truths.xray, renderGroundTruth(scene, crop, xray)).maxAbs, 1e-6);
    EXPECT_GT(compareImages(truths.xray, truths.attenuating).maxAbs, 1e-3) << "X-ray has a truth of its own";
    SplatRenderer gl;
    gl.setScene(scene);
    const std::vector<FilterMeasurement> points = measureSpeedAgainstError(gl, view, crop, truths, base, 2);
    const std::vector<SplatSettings> settings = speedErrorSettings(base);
    ASSERT_EQ(points.size(), settings.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const FilterMeasurement& m = points[i];
        const std::string what = std::string(filterModeName(m.filter)) + ", " + compositingName(m.compositing);
        EXPECT_EQ(m.filter, settings[i].filter);
        EXPECT_EQ(m.compositing, settings[i].compositing);
        EXPECT_EQ(m.frames, 2);
        EXPECT_GT(m.p10Ms, 0.0) << what;
        EXPECT_LE(m.p10Ms, m.frameMs) << what;
        EXPECT_LE(m.frameMs, m.p90Ms) << what;
        const ImageError e = cropError(gl, crop, truths.of(settings[i]), settings[i]);
        EXPECT_NEAR(m.psnrDb, e.psnrDb, 1e-3) << what;
        EXPECT_LT(m.rmse, 0.1) << what << ": compared with another setting's truth?";
    }
}

TEST_F(GlTest, SlabsAreMeasuredAgainstTheirOwnTruthPostClassifiedAgainstThePostClassifiedOne) {
    // The editor's Measure with Settings > Image-aligned slabs on: the slabs in force timed on the view and
    // their crop compared with the truth of their model, the post-classified one where they post-classify.
    MeasuredView measured;
    measured.settings.compositing = Compositing::SheetFrontToBack;
    const auto& [scene, view, crop, settings] = measured;
    const CropTruths truths =
        cropTruths(scene, crop, settings, {}, testing_support::testOutputDir("speed_error_cache"), {}, true);
    GroundTruthOptions post;
    post.postClassified = true;
    EXPECT_LT(compareImages(truths.postClassified, renderGroundTruth(scene, crop, settings, post)).maxAbs, 1e-6);
    ImageSlabsGl pass;
    for (const bool postClassified : {false, true}) {
        const SlabOptions slabs{.thickness = 0.5, .postClassified = postClassified};
        int drawn = 0;
        const auto draw = [&](const ImagePlane& p) { return ++drawn, pass.render(scene, p, settings, slabs); };
        const FilterMeasurement m = measureSlabs(draw, view, crop, truths.ofSlabs(slabs), settings, slabs, 3);
        EXPECT_EQ(drawn, 4) << "three timed frames of the view, then the crop";
        EXPECT_EQ(m.frames, 3);
        EXPECT_EQ(m.slabThickness, 0.5);
        EXPECT_EQ(m.postClassified, postClassified);
        EXPECT_LE(m.p10Ms, m.frameMs);
        EXPECT_LE(m.frameMs, m.p90Ms);
        const ImageError own = compareImages(renderImageAlignedSlabs(scene, crop, settings, slabs), truths.ofSlabs(slabs));
        EXPECT_NEAR(m.psnrDb, own.psnrDb, 0.05) << "GL's crop, within the GL-oracle tolerance of the oracle's";
        const ImageError other = compareImages(pass.render(scene, crop, settings, slabs),
                                               postClassified ? truths.attenuating : truths.postClassified);
        EXPECT_GT(m.psnrDb, other.psnrDb + 3.0) << "closer to its own model's truth than to the other's";
        std::printf("[ slab measure ] %s: %.2f dB against its truth, %.2f dB against the other\n",
                    postClassified ? "post-classified" : "pre-classified", m.psnrDb, other.psnrDb);
    }
}
