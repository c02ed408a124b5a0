// Gradient opacity on the GL path: the same factor a voxel as the CPU oracle (kGlVsCpu), rasterised,
// tiled and in the near layer, and a factor of 1 everywhere leaves the image as it was.
#include "gl_fixture.h"
#include "image_compare.h"

#include "renderer/gl/splat_renderer.h"
#include "renderer/math/metrics.h"
#include "renderer/model/gradients.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/reference_renderer.h"

using namespace renderer;

namespace {

TransferFunction ramp() {
    return fromSharedPoints(
        "test-ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.3, {0.3, 0.9, 0.4}, 0.2}, {1.0, {1.0, 0.8, 0.3}, 0.9}});
}

struct Scenes {
    Volume volume;
    GradientField field;
    double meanMagnitude = 0.0;
};

const Scenes& marschnerLobb() {
    static const Scenes s = [] {
        Scenes out;
        out.volume = makeMarschnerLobb(20);
        out.field = *computeGradients(out.volume);
        out.meanMagnitude = gradientMagnitudeStats(out.field).mean;
        return out;
    }();
    return s;
}

SplatScene sceneWith(const TransferFunction& tf) {
    SplatScene scene = buildSplatScene(marschnerLobb().volume, tf);
    addGradients(scene, marschnerLobb().field);
    return scene;
}

// A ramp from 0 below half the mean magnitude to 1 at twice it: partial factors over most voxels.
TransferFunction faded() {
    TransferFunction tf = ramp();
    const double m = marschnerLobb().meanMagnitude;
    tf.gradientOpacity = {{0.5 * m, 0.0}, {2.0 * m, 1.0}};
    return tf;
}

} // namespace

TEST_F(GlTest, GradientOpacityMatchesCpuRasterisedTiledAndShaded) {
    const SplatScene scene = sceneWith(faded());
    ASSERT_EQ(scene.gradientFactors.size(), size_t(kGradientBins));
    const SplatScene plainScene = sceneWith(ramp());
    const ImagePlane plane = makeImagePlane(Camera{35, 25, 2.2, 40.0}, scene.centre, scene.radius, 48, 40);
    SplatRenderer r;
    r.setScene(scene);
    struct Variant {
        const char* name;
        SplatSettings::Primitive primitive;
        SplatSettings::Shading shading;
        FilterMode filter;
    };
    for (const Variant& v :
         {Variant{"quads", SplatSettings::Primitive::Quads, SplatSettings::Shading::None, FilterMode::Ewa},
          Variant{"tiles", SplatSettings::Primitive::Tiles, SplatSettings::Shading::None, FilterMode::Ewa},
          Variant{"tiles_shaded", SplatSettings::Primitive::Tiles, SplatSettings::Shading::PerSplat,
                  FilterMode::Adaptive}}) {
        SplatSettings s;
        s.primitive = v.primitive;
        s.compositing = Compositing::SheetBackToFront; // tiles composite sheets
        s.shading = v.shading;
        s.filter = v.filter;
        s.counters = true;
        r.render(plane, s);
        SplatCounters cpu, plain;
        const Image expected = renderReference(scene, plane, s, &cpu);
        renderReference(plainScene, plane, s, &plain);
        EXPECT_GT(cpu.culledTransparent, plain.culledTransparent + 300) << "the factor must cull voxels";
        ASSERT_TRUE(r.stats().hasCounters);
        expectCountersEqual(r.stats().counters, cpu);
        EXPECT_IMAGES_CLOSE(r.readback(), expected, kGlVsCpu, std::string("gl_gradient_opacity_") + v.name);
    }
}

TEST_F(GlTest, GradientOpacityFadesTheNearLayerAsTheCpu) {
    const SplatScene scene = sceneWith(faded());
    // The eye at the volume's centre: kernels at the near plane go to the near layer.
    const ImagePlane plane = makeImagePlane(Camera{20, 10, 1e-3, 60.0}, scene.centre, scene.radius, 48, 48);
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s;
    s.counters = true;
    r.render(plane, s);
    SplatCounters cpu;
    const Image expected = renderReference(scene, plane, s, &cpu);
    ASSERT_GT(cpu.nearLayer, 0u) << "the view must have a near layer";
    expectCountersEqual(r.stats().counters, cpu);
    EXPECT_IMAGES_CLOSE(r.readback(), expected, kGlVsCpu, "gl_gradient_opacity_near");
}

TEST_F(GlTest, GradientOpacityOfOneEverywhereLeavesTheImageAndATfEditUploadsOnlyTheTables) {
    TransferFunction one = ramp();
    one.gradientOpacity = {{0.0, 1.0}};
    SplatScene scene = sceneWith(ramp());
    const ImagePlane plane = makeImagePlane(Camera{35, 25, 2.2, 40.0}, scene.centre, scene.radius, 48, 40);
    SplatRenderer r;
    r.setScene(scene);
    for (auto primitive : {SplatSettings::Primitive::Quads, SplatSettings::Primitive::Tiles}) {
        SplatSettings s;
        s.primitive = primitive;
        s.compositing = Compositing::SheetBackToFront;
        setTransferFunction(scene, ramp());
        r.setLut(tfTables(scene));
        r.render(plane, s);
        const Image before = r.readback();
        setTransferFunction(scene, one);
        r.setLut(tfTables(scene));
        EXPECT_EQ(r.stats().uploadBytes, size_t(kLutSize + kGradientBins) * sizeof(glm::vec4));
        r.render(plane, s);
        // Rasterised splats blend in a fixed order: the same bits. Tiles add a sheet's splats in the order
        // their threads reach the tile lists, so two frames of the same TF differ by float rounding.
        if (primitive == SplatSettings::Primitive::Quads)
            EXPECT_EQ(r.readback().rgba, before.rgba) << primitiveName(r.stats());
        else
            EXPECT_IMAGES_CLOSE(r.readback(), before, kGlVsCpu, "gl_gradient_opacity_one_tiles");
        // And the edit to a real ramp changes it, with no new scene.
        setTransferFunction(scene, faded());
        r.setLut(tfTables(scene));
        r.render(plane, s);
        EXPECT_GT(compareImages(r.readback(), before).rmse, 1e-3) << primitiveName(r.stats());
    }
}
