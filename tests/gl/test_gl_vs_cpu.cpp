// The GL path against the CPU oracle on small scenes. Both composite the same splats in the same
// order; they differ only in float vs double arithmetic.
//
// Tolerance, per channel: abs 2e-5 + rel 2e-4. The vertex stage computes the footprint in float
// (relative error ~1e-6 per operation, ~30 operations), and blending ~100 layers in float adds ~1e-6
// absolute: measured on llvmpipe, mean |GL - CPU| 0.6e-7..5.4e-7 and max 1.2e-6..4.7e-6 away from
// cutoff edges. The exception is a pixel whose centre lies on a cutoff ellipse (e == cutoff^2 to
// ~1e-6): float and double may disagree on whether it is in, a jump of up to amplitude x
// exp(-cutoff^2/2), 1.1 % of that splat's peak (measured worst 1.4e-4). So 0.5 % of the pixels may
// fail, no channel may be off by more than 1e-2, and the mean must stay under 2e-6 (x4 the worst
// measured) so a slow drift cannot hide among the edge pixels.
#include "gl_fixture.h"
#include "image_compare.h"
#include "test_paths.h"

#include "renderer/errors.h"
#include "renderer/hard_cases.h"
#include "renderer/procedural.h"
#include "renderer/reference_renderer.h"
#include "renderer/splat_renderer.h"
#include "renderer/volume_io.h"

using namespace renderer;
using testing_support::Tolerance;

namespace {

const Tolerance kGlVsCpu{.abs = 2e-5, .rel = 2e-4, .maxBadFraction = 0.005, .maxMeanAbs = 2e-6, .maxAbs = 1e-2};

TransferFunction ramp() {
    return {"test-ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.3, {0.3, 0.9, 0.4}, 0.2}, {1.0, {1.0, 0.8, 0.3}, 0.9}}};
}

struct Case {
    Image gl, cpu;
    SplatCounters counters;
};

Case renderBoth(const Volume& v, const TransferFunction& tf, const Camera& cam, const SplatSettings& s, int w,
                int h) {
    const SplatScene scene = buildSplatScene(v, tf);
    const ImagePlane plane = makeImagePlane(cam, scene.centre, scene.radius, w, h);
    SplatRenderer r;
    r.setScene(scene);
    r.render(plane, s);
    Case c;
    c.gl = r.readback();
    c.cpu = renderReference(scene, plane, s, &c.counters);
    return c;
}

} // namespace

TEST_F(GlTest, PerspectiveWithSplatsAcrossTheBorderMatchesCpu) {
    // Close camera: the volume overflows the 96x80 image on every side, so splats straddle the border.
    const Volume v = makeMarschnerLobb(20);
    Camera cam{.azimuthDeg = 35, .elevationDeg = 25, .distance = 1.3, .fovYDeg = 60};
    const Case c = renderBoth(v, ramp(), cam, SplatSettings{}, 96, 80);
    EXPECT_GT(c.counters.drawn, 1000u);
    const ImageStats s = imageStats(c.cpu);
    EXPECT_GT(s.coveredFraction, 0.95) << "the scene must fill the frame to test the border";
    EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, "gl_vs_cpu_border");
}

TEST_F(GlTest, RectilinearVolumeMatchesCpu) {
    Volume v = makeSphereShells(18, 6.0, 2.0);
    v.spacing = {3.2, 3.2, 1.5};   // headsq's spacing: elliptical kernels
    const Case c = renderBoth(v, ramp(), Camera{.azimuthDeg = 60, .elevationDeg = 35, .distance = 2.2}, SplatSettings{},
                              96, 96);
    EXPECT_GT(imageStats(c.cpu).meanAlpha, 0.05);
    EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, "gl_vs_cpu_rectilinear");
}

TEST_F(GlTest, XRayMatchesCpu) {
    const Volume v = makeMarschnerLobb(18);
    SplatSettings s;
    s.compositing = Compositing::XRay;
    const Case c = renderBoth(v, ramp(), Camera{.azimuthDeg = 10, .elevationDeg = -30, .distance = 2.5}, s, 80, 80);
    EXPECT_GT(imageStats(c.cpu).meanAlpha, 0.05);
    EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, "gl_vs_cpu_xray");
}

TEST_F(GlTest, EveryFilterModeMatchesCpu) {
    const Volume v = makeSphereShells(16, 5.0, 2.0);
    for (auto mode : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa}) {
        SplatSettings s;
        s.filter = mode;
        const Case c = renderBoth(v, ramp(), Camera{.azimuthDeg = 200, .elevationDeg = 10, .distance = 3.0}, s, 64, 64);
        EXPECT_GT(imageStats(c.cpu).meanAlpha, 0.02) << filterModeName(mode);
        EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, std::string("gl_vs_cpu_") + filterModeName(mode));
    }
}

TEST_F(GlTest, BundledHeadsqMatchesCpu) {
    const Volume v = loadVolume(testing_support::assetDir() / "volumes" / "headsq.nhdr");
    const Case c = renderBoth(v, builtinPreset("ct-skin-bone"), Camera{}, SplatSettings{}, 128, 128);
    EXPECT_GT(imageStats(c.cpu).meanAlpha, 0.1);
    writeImage(c.gl, testing_support::testOutputDir() / "headsq_gl.png");   // for a person to look at
    EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, "gl_vs_cpu_headsq");
}

TEST_F(GlTest, FrameUploadsNothingPerSplat) {
    const SplatScene scene = buildSplatScene(makeSphereShells(16, 5.0, 2.0), ramp());
    SplatRenderer r;
    r.setScene(scene);
    EXPECT_GT(r.stats().uploadBytes, 0u);
    r.render(makeImagePlane(Camera{}, scene.centre, scene.radius, 32, 32), SplatSettings{});
    EXPECT_EQ(r.stats().uploadBytes, 0u);
    EXPECT_EQ(r.stats().splatsDrawn, scene.visibleCount());
    // Classes (2 bytes) plus three index lists (4 bytes per visible voxel each) plus the LUT.
    const double perVoxel = double(r.sceneBytes() - kLutSize * 16) / double(scene.classes.size());
    EXPECT_LE(perVoxel, 2.0 + 12.0 * double(scene.visibleCount()) / double(scene.classes.size()) + 1e-9);
}

TEST_F(GlTest, AdaptivePerPatchMatchesCpu) {
    // Close, wide view of a deep volume so near patches are magnified and far ones are not: the GL
    // vertex stage classifies patches exactly as the CPU classifier does.
    Volume v = makeSphereShells(20, 5.0, 2.0);
    v.spacing = {1.0, 1.0, 4.0};
    SplatSettings s;
    s.filter = FilterMode::Adaptive;
    s.patchSize = 4;
    s.cMin = 0.6;   // a wider reconstruction band, so all three modes appear at this size
    const Case c = renderBoth(v, ramp(), Camera{.azimuthDeg = 20, .elevationDeg = 15, .distance = 1.15, .fovYDeg = 70},
                              s, 128, 128);
    EXPECT_GT(c.counters.drawnPerMode[0], 0u);
    EXPECT_GT(c.counters.drawnPerMode[2], 0u);
    EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, "gl_vs_cpu_adaptive");
}

TEST_F(GlTest, OrthographicMatchesCpu) {
    Volume v = makeMarschnerLobb(16);
    v.spacing = {1.0, 2.0, 1.0};
    const Case c = renderBoth(v, ramp(),
                              Camera{.azimuthDeg = 50, .elevationDeg = 30, .distance = 2.5, .orthographic = true},
                              SplatSettings{}, 80, 64);
    EXPECT_GT(imageStats(c.cpu).meanAlpha, 0.05);
    EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, "gl_vs_cpu_ortho");
}

TEST_F(GlTest, SheetCompositingSaysItIsCpuOnly) {
    const SplatScene scene = buildSplatScene(makeSphereShells(8, 4.0, 2.0), ramp());
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    try {
        r.render(makeImagePlane(Camera{}, scene.centre, scene.radius, 16, 16), s);
        ADD_FAILURE() << "sheet compositing rendered on GL";
    } catch (const RenderError& e) {
        EXPECT_NE(std::string(e.what()).find("CPU oracle only"), std::string::npos) << e.what();
    }
}

TEST_F(GlTest, HardCasesStayFiniteAndMatchCpu) {
    // The CPU suite checks each hard case against the ground truth; here GL must agree with the CPU
    // on them too, float precision included (volume 1e6 units away, fov 1 and 170 degrees).
    for (const HardCase& hc : hardCases(1)) {
        for (auto mode : {FilterMode::Ewa, FilterMode::Adaptive}) {
            SplatSettings s = hc.settings;
            s.filter = mode;
            const Case c = renderBoth(hc.volume, hc.tf, hc.camera, s, hc.width, hc.height);
            EXPECT_TRUE(imageStats(c.gl).finite) << hc.name;
            EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, "hard_" + hc.name + "_" + filterModeName(mode));
        }
    }
}
