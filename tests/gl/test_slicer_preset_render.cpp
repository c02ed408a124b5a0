// A 3D Slicer preset renders as the same TF typed by hand: the GL path with the imported TF against the CPU
// oracle with the typed one, within the GL-vs-CPU tolerance (gl_fixture.h).
#include "gl_fixture.h"
#include "image_compare.h"
#include "test_paths.h"

#include "renderer/gl/splat_renderer.h"
#include "renderer/model/procedural.h"
#include "renderer/model/slicer_preset.h"

using namespace renderer;

TEST_F(GlTest, ASlicerPresetRendersAsTheSameTfTypedByHand) {
    // CT-Bone as Slicer's presets.xml gives it.
    const auto path = testing_support::testOutputDir("slicer") / "ct_bone.xml";
    ASSERT_TRUE(testing_support::writeFile(path, R"(<?xml version="1.0" encoding="utf-8"?>
<MRML>
  <VolumeProperty name="CT-Bone" gradientOpacity="4 0 1 255 1" specularPower="10"
    scalarOpacity="8 -3024 0 -16.4458 0 641.385 0.715686 3071 0.705882" shade="1"
    colorTransfer="16 -3024 0 0 0 -16.4458 0.729412 0.254902 0.301961 641.385 0.905882 0.815686 0.552941 3071 1 1 1"/>
</MRML>
)"));
    TransferFunction byHand;
    byHand.name = "CT-Bone";
    byHand.opacities = {{-3024, 0.0}, {-16.4458, 0.0}, {641.385, 0.715686}, {3071, 0.705882}};
    byHand.colours = {{-3024, {0, 0, 0}},
                      {-16.4458, {0.729412, 0.254902, 0.301961}},
                      {641.385, {0.905882, 0.815686, 0.552941}},
                      {3071, {1, 1, 1}}};
    const TransferFunction imported = loadSlicerPresets(path).front().tf;

    // Shells with CT-like values: air at -1000 up to bone at 1500 HU.
    Volume v = makeSphereShells(20, 6.0, 2.0);
    const ValueRange unit = v.range;
    for (float& x : v.values.floats())
        x = -1000.0f + 2500.0f * (x - unit.lo) / (unit.hi - unit.lo);
    updateRange(v);
    const SplatScene importedScene = buildSplatScene(v, imported), typedScene = buildSplatScene(v, byHand);
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 40, .elevationDeg = 25, .distance = 2.2},
                                            typedScene.centre, typedScene.radius, 96, 96);
    SplatRenderer r;
    r.setScene(importedScene);
    r.render(plane, SplatSettings{});
    const Image gl = r.readback();
    const Image cpu = renderReference(typedScene, plane, SplatSettings{});
    EXPECT_GT(imageStats(cpu).meanAlpha, 0.05)
        << "CT-Bone shows nothing of the shells: the test compares two blanks";
    EXPECT_IMAGES_CLOSE(gl, cpu, kGlVsCpu, "slicer_ct_bone_gl_vs_typed_cpu");
}
