// The 2D transfer function on the GL path: each voxel's colour and opacity by its (value, magnitude) cell
// as the CPU oracle (kGlVsCpu), rasterised and tiled, unshaded and shaded, and in the near layer; a TF
// edit uploads the table with the LUT, the first one making room for it.
#include "gl_fixture.h"
#include "image_compare.h"

#include "renderer/gl/splat_renderer.h"
#include "renderer/math/metrics.h"
#include "renderer/model/gradients.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/reference_renderer.h"

using namespace renderer;

namespace {

struct Fixture {
    Volume volume;
    GradientField field;
    double meanMagnitude = 0.0;
};

const Fixture& marschnerLobb() {
    static const Fixture f = [] {
        Fixture out;
        out.volume = makeMarschnerLobb(20);
        out.field = *computeGradients(out.volume);
        out.meanMagnitude = gradientMagnitudeStats(out.field).mean;
        return out;
    }();
    return f;
}

// A triangle on the upper values' boundaries (partial weights, in orange) and a rectangle of strong
// gradients over the lower values (blue): colours that vary with the gradient within one class.
TransferFunction twoWidgets() {
    const Fixture& f = marschnerLobb();
    const double lo = f.volume.range.lo, span = double(f.volume.range.hi) - f.volume.range.lo;
    const double m = f.meanMagnitude;
    TransferFunction tf = fromSharedPoints("ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {1.0, {1.0, 0.8, 0.3}, 0.9}});
    tf = inDataUnits(tf, f.volume.range);
    Widget2D triangle;
    triangle.shape = WidgetShape::Triangle;
    triangle.apex = lo + 0.6 * span, triangle.halfWidth = 0.3 * span, triangle.magnitudeTop = 2.0 * m;
    triangle.colour = {1.0, 0.6, 0.1}, triangle.opacity = 0.9;
    Widget2D rectangle;
    rectangle.valueLo = lo + 0.1 * span, rectangle.valueHi = lo + 0.55 * span;
    rectangle.magnitudeLo = 0.8 * m, rectangle.magnitudeHi = 1e9;
    rectangle.colour = {0.2, 0.4, 1.0}, rectangle.opacity = 0.5;
    tf.widgets2d = {triangle, rectangle};
    return tf;
}

SplatScene sceneWith(const TransferFunction& tf) {
    SplatScene scene = buildSplatScene(marschnerLobb().volume, tf);
    addGradients(scene, marschnerLobb().field);
    return scene;
}

} // namespace

TEST_F(GlTest, Tf2dMatchesCpuRasterisedTiledShadedAndNot) {
    const SplatScene scene = sceneWith(twoWidgets());
    ASSERT_EQ(scene.tf2d.size(), size_t(kTf2dCells));
    const ImagePlane plane = makeImagePlane(Camera{35, 25, 2.2, 40.0}, scene.centre, scene.radius, 48, 40);
    SplatRenderer r;
    r.setScene(scene);
    using Shading = SplatSettings::Shading;
    using Primitive = SplatSettings::Primitive;
    struct Variant {
        const char* name;
        Primitive primitive;
        Shading shading;
        FilterMode filter;
    };
    for (const Variant& v : {Variant{"quads", Primitive::Quads, Shading::None, FilterMode::Ewa},
                             Variant{"quads_fragment", Primitive::Quads, Shading::PerFragment, FilterMode::Ewa},
                             Variant{"tiles", Primitive::Tiles, Shading::None, FilterMode::Ewa},
                             Variant{"tiles_splat", Primitive::Tiles, Shading::PerSplat, FilterMode::Adaptive},
                             Variant{"tiles_fragment", Primitive::Tiles, Shading::PerFragment, FilterMode::Ewa}}) {
        SplatSettings s;
        s.primitive = v.primitive;
        s.compositing = Compositing::SheetBackToFront;   // tiles composite sheets
        s.shading = v.shading;
        s.filter = v.filter;
        s.counters = true;
        r.render(plane, s);
        SplatCounters cpu;
        const Image expected = renderReference(scene, plane, s, &cpu);
        EXPECT_GT(cpu.culledTransparent, 500u) << "cells outside the widgets must cull voxels";
        ASSERT_TRUE(r.stats().hasCounters);
        expectCountersEqual(r.stats().counters, cpu);
        EXPECT_IMAGES_CLOSE(r.readback(), expected, kGlVsCpu, std::string("gl_tf2d_") + v.name);
    }
}

TEST_F(GlTest, Tf2dColoursTheNearLayerAsTheCpu) {
    const SplatScene scene = sceneWith(twoWidgets());
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
    EXPECT_IMAGES_CLOSE(r.readback(), expected, kGlVsCpu, "gl_tf2d_near");
}

TEST_F(GlTest, Tf2dEditUploadsTheTableAndRemovingTheWidgetsGivesThe1dImageBack) {
    TransferFunction plain = twoWidgets();
    plain.widgets2d.clear();
    SplatScene scene = sceneWith(plain);
    const ImagePlane plane = makeImagePlane(Camera{35, 25, 2.2, 40.0}, scene.centre, scene.radius, 48, 40);
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s;
    s.primitive = SplatSettings::Primitive::Tiles;
    s.compositing = Compositing::SheetBackToFront;
    r.render(plane, s);
    const Image before = r.readback();
    const uint64_t bytesWithout = r.sceneBytes();
    setTransferFunction(scene, twoWidgets());
    r.setLut(tfTables(scene));
    EXPECT_EQ(r.stats().uploadBytes, size_t(kLutSize + kTf2dCells) * sizeof(glm::vec4));
    EXPECT_EQ(r.sceneBytes(), bytesWithout + size_t(kTf2dCells) * sizeof(glm::vec4))
        << "the cells' room comes with the first 2D TF, not with every scene";
    r.render(plane, s);
    EXPECT_GT(compareImages(r.readback(), before).rmse, 1e-3) << "the widgets must change the image";
    EXPECT_IMAGES_CLOSE(r.readback(), renderReference(scene, plane, s), kGlVsCpu, "gl_tf2d_edit");
    setTransferFunction(scene, plain);
    r.setLut(tfTables(scene));
    r.render(plane, s);
    EXPECT_IMAGES_CLOSE(r.readback(), before, kGlVsCpu, "gl_tf2d_removed");
}
