// The GL path against the CPU oracle on small scenes (tolerance: gl_fixture.h).
#include "gl_fixture.h"
#include "image_compare.h"
#include "test_paths.h"

#include "renderer/errors.h"
#include "renderer/oracle/hard_cases.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/io/volume_io.h"

using namespace renderer;

namespace {

TransferFunction ramp() {
    return fromSharedPoints("test-ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.3, {0.3, 0.9, 0.4}, 0.2}, {1.0, {1.0, 0.8, 0.3}, 0.9}});
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
    s.primitive = SplatSettings::Primitive::Raster;   // the rasteriser's X-ray (tiles: test_gl_tiles.cpp)
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
    EXPECT_IMAGES_CLOSE(c.gl, c.cpu, kGlVsCpu, "gl_vs_cpu_headsq");
    writeImage(c.gl, testing_support::testOutputDir() / "headsq_gl.png");   // last, for a person to look at
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
