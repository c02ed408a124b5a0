// Image-aligned slabs on the GPU (renderer/gl/image_slabs_gl.h) against the CPU oracle's slabs: the same
// kernels, shares and order, float against double. Pre- and post-classified, shaded and unshaded,
// perspective and orthographic, on hard cases whose kernels overlap in depth.
#include "gl_fixture.h"

#include "renderer/errors.h"
#include "renderer/gl/image_slabs_gl.h"
#include "renderer/math/metrics.h"
#include "renderer/model/gradients.h"
#include "renderer/oracle/hard_cases.h"
#include "renderer/io/volume_io.h"
#include "renderer/oracle/image_slabs.h"
#include "test_paths.h"

#include <cstdio>

using namespace renderer;

namespace {

struct Case {
    const char* name;
    SplatSettings::Shading shading;
    bool post;
    double thickness;
};

} // namespace

TEST_F(GlTest, ImageAlignedSlabsMatchTheOracle) {
    const Case cases[] = {
        {"marschner-lobb", SplatSettings::Shading::None, false, 0.5},
        {"marschner-lobb", SplatSettings::Shading::PerFragment, false, 0.25},
        {"marschner-lobb", SplatSettings::Shading::PerSplat, true, 0.5},
        {"orthographic", SplatSettings::Shading::None, true, 0.25},
        {"orthographic", SplatSettings::Shading::PerFragment, true, 0.5},
        {"zebra", SplatSettings::Shading::None, false, 1.0},
        {"huge-coordinates", SplatSettings::Shading::None, false, 0.5},
        {"nan-inf-values", SplatSettings::Shading::PerFragment, true, 0.5},
        {"near-plane", SplatSettings::Shading::None, false, 0.5},   // the near layer, on the CPU for both
    };
    const ImageSlabsGl pass;
    for (const Case& c : cases) {
        HardCase hc = hardCases(1, c.name).at(0);
        SplatScene scene = buildSplatScene(hc.volume, hc.tf);
        addGradients(scene, *computeGradients(hc.volume));
        const ImagePlane plane = makeImagePlane(hc.camera, scene.centre, scene.radius, hc.width, hc.height);
        hc.settings.shading = c.shading;
        const SlabOptions options{c.thickness, c.post};
        SlabCounters cpuWork, glWork;
        const Image cpu = renderImageAlignedSlabs(scene, plane, hc.settings, options, &cpuWork);
        const Image gl = pass.render(scene, plane, hc.settings, options, &glWork);
        const ImageError d = renderer::compareImages(gl, cpu);
        std::printf("[ gl slabs ] %-16s %-12s %s %.2f voxels: max |GL - CPU| %.2e, PSNR %.1f dB; %llu / %llu slab writes\n",
                    c.name, shadingName(c.shading), c.post ? "post" : "pre ", c.thickness, d.maxAbs, d.psnrDb,
                    (unsigned long long)glWork.slabWrites, (unsigned long long)cpuWork.slabWrites);
        const std::string what = std::string(c.name) + (c.post ? "_post" : "_pre") + "_" + shadingName(c.shading);
        EXPECT_IMAGES_CLOSE(gl, cpu, kGlVsCpu, ("gl_slabs_" + what).c_str());
        EXPECT_GT(imageStats(cpu).maxAlpha, 0.05) << what << ": the case must draw something";
        EXPECT_EQ(glWork.slabs, cpuWork.slabs) << what;
        EXPECT_NEAR(double(glWork.footprintPixels), double(cpuWork.footprintPixels), 0.001 * double(cpuWork.footprintPixels) + 2)
            << what;
    }
}

// Resolved from 2x2 samples a pixel as the oracle is; refused as the oracle refuses.
TEST_F(GlTest, ImageAlignedSlabsSupersampleAndRefuseAsTheOracle) {
    const HardCase hc = hardCases(1, "marschner-lobb").at(0);
    const SplatScene scene = buildSplatScene(hc.volume, hc.tf);
    const ImagePlane plane = makeImagePlane(hc.camera, scene.centre, scene.radius, hc.width, hc.height);
    SplatSettings s = hc.settings;
    s.filter = FilterMode::Reconstruction;
    const SlabOptions resolved{0.5, true, 2};
    const ImageSlabsGl pass;
    EXPECT_IMAGES_CLOSE(pass.render(scene, plane, s, resolved),
                        renderImageAlignedSlabs(scene, plane, s, resolved), kGlVsCpu, "gl_slabs_supersampled");
    EXPECT_THROW(pass.render(scene, plane, s, SlabOptions{0.5, false, 5}), RenderError);
    s.compositing = Compositing::XRay;
    EXPECT_THROW(pass.render(scene, plane, s, SlabOptions{0.5}), RenderError);
    s.compositing = Compositing::SheetFrontToBack;
    EXPECT_THROW(pass.render(scene, plane, s, SlabOptions{0.01}), RenderError);
}

// A real scan with tile lists thousands of kernels long: on llvmpipe, which ends a shader's loops after
// 65535 iterations, the pass takes them in several dispatches, each pixel's state carried between them
// (before it did, some pixels silently lost most of their kernels).
TEST_F(GlTest, ImageAlignedSlabsTakeLongTileListsWhole) {
    const Volume bonsai = loadVolume(testing_support::assetDir() / "volumes" / "bonsai.nhdr");
    const SplatScene scene = buildSplatScene(bonsai, loadTransferFunction(testing_support::assetDir() / "presets" / "bonsai.json"));
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, 32, 32);
    SplatSettings s;
    s.opaqueAlpha = 1.0;   // every kernel reaches every pixel it covers: the counts must agree
    SlabCounters cpuWork, glWork;
    const ImageSlabsGl pass;
    const Image cpu = renderImageAlignedSlabs(scene, plane, s, SlabOptions{0.5}, &cpuWork);
    const Image gl = pass.render(scene, plane, s, SlabOptions{0.5}, &glWork);
    std::printf("[ gl slabs ] bonsai 32x32: %llu / %llu footprint pixels, max |GL - CPU| %.2e\n",
                (unsigned long long)glWork.footprintPixels, (unsigned long long)cpuWork.footprintPixels,
                renderer::compareImages(gl, cpu).maxAbs);
    EXPECT_NEAR(double(glWork.footprintPixels), double(cpuWork.footprintPixels), 1e-4 * double(cpuWork.footprintPixels));
    EXPECT_IMAGES_CLOSE(gl, cpu, kGlVsCpu, "gl_slabs_bonsai");
    // Early termination: a pixel that turns opaque stops walking its list (only its open slabs remain).
    s.opaqueAlpha = 0.998;
    SlabCounters cpuEarly, glEarly;
    EXPECT_IMAGES_CLOSE(pass.render(scene, plane, s, SlabOptions{0.5}, &glEarly),
                        renderImageAlignedSlabs(scene, plane, s, SlabOptions{0.5}, &cpuEarly), kGlVsCpu,
                        "gl_slabs_bonsai_early");
    EXPECT_LT(double(cpuEarly.footprintPixels), 0.9 * double(cpuWork.footprintPixels)) << "the pot turns opaque";
    EXPECT_NEAR(double(glEarly.footprintPixels), double(cpuEarly.footprintPixels), 1e-3 * double(cpuEarly.footprintPixels));
}
