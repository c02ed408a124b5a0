// A GPU's tiled frames read nothing back while they run (DriverProfile::deferredListChecks): their lists
// take a capacity from earlier frames, and a frame whose lists were too short is drawn again, once, before
// its image is read or displayed. The GPU's profile is forced on this driver (SPLATLAB_DRIVER_PROFILE), and
// the reads are counted through the renderer's one buffer-read wrapper (FrameStats::readBacks).
#include "gl_fixture.h"
#include "scoped_env.h"

#include "renderer/gl/splat_renderer.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/reference_renderer.h"

using namespace renderer;
using testing_support::ScopedEnv;

namespace {

TransferFunction ramp() {
    return fromSharedPoints("test-ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.3, {0.3, 0.9, 0.4}, 0.2}, {1.0, {1.0, 0.8, 0.3}, 0.9}});
}

SplatSettings tiled(Compositing mode) {
    SplatSettings s;
    s.compositing = mode;
    s.primitive = SplatSettings::Primitive::Tiles;
    s.density = 4.0;   // front to back: opaque enough that early termination stops pixels
    return s;
}

} // namespace

TEST_F(GlTest, AGpusTiledFramesReadNothingBackWhileTheyRun) {
    // Three frames of each mode: none reads a buffer while it runs, each gives the oracle's image, and
    // after the first the lists are sized from the frame before, so none is drawn again. llvmpipe's own
    // profile reads each part's list sizes: the count sees reads where there are some.
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(20), ramp());
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 35, .elevationDeg = 25}, scene.centre, scene.radius, 64, 56);
    for (auto mode : {Compositing::SheetBackToFront, Compositing::SheetFrontToBack, Compositing::XRay}) {
        const std::string name = std::string("gl_deferred_") + compositingName(mode);
        SCOPED_TRACE(name);
        const SplatSettings s = tiled(mode);
        const Image cpu = renderReference(scene, plane, s);
        ASSERT_GT(imageStats(cpu).coveredFraction, 0.2);
        {
            const ScopedEnv software("SPLATLAB_DRIVER_PROFILE", "llvmpipe");
            SplatRenderer r;
            r.setScene(scene);
            r.render(plane, s);
            EXPECT_GE(r.stats().readBacks, 1) << "llvmpipe's profile reads each part's list sizes";
            EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, name + "_llvmpipe");
        }
        const ScopedEnv gpu("SPLATLAB_DRIVER_PROFILE", "gpu");
        SplatRenderer r;
        r.setScene(scene);
        for (int frame = 0; frame < 3; ++frame) {
            r.render(plane, s);
            EXPECT_EQ(r.stats().readBacks, 0) << "frame " << frame;
            EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, name + "_" + std::to_string(frame));
            if (frame > 0) {
                EXPECT_FALSE(r.stats().redone) << "frame " << frame << ": sized from the frame before";
            }
            EXPECT_GT(r.stats().tileEntries, 0u) << "known once the image is read";
        }
    }
}

TEST_F(GlTest, AGpusFrameWhoseListsWereTooShortIsDrawnAgainOnceBeforeItsImageIsUsed) {
    // A far view sizes the lists; the camera then comes close, where footprints span many more tiles: that
    // frame's lists overflow, it is drawn again the checked way when read, and the frames after it fit.
    const ScopedEnv gpu("SPLATLAB_DRIVER_PROFILE", "gpu");
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(20), ramp());
    const ImagePlane far = makeImagePlane(Camera{.azimuthDeg = 35, .elevationDeg = 25, .distance = 6}, scene.centre,
                                          scene.radius, 100, 84);
    const ImagePlane near = makeImagePlane(Camera{.azimuthDeg = 35, .elevationDeg = 25, .distance = 1.4},
                                           scene.centre, scene.radius, 100, 84);
    const SplatSettings s = tiled(Compositing::SheetBackToFront);
    SplatRenderer r;
    r.setScene(scene);
    r.render(far, s);
    EXPECT_IMAGES_CLOSE(r.readback(), renderReference(scene, far, s), kGlVsCpu, "gl_deferred_far");
    const uint64_t farEntries = r.stats().tileEntries;

    const Image cpuNear = renderReference(scene, near, s);
    r.render(near, s);
    EXPECT_EQ(r.stats().readBacks, 0);
    EXPECT_FALSE(r.stats().redone) << "not known before the image is used";
    const Image redone = r.readback();
    EXPECT_TRUE(r.stats().redone);
    EXPECT_GT(r.stats().tileEntries, 2 * farEntries) << "the close view must overflow the far view's lists";
    EXPECT_IMAGES_CLOSE(redone, cpuNear, kGlVsCpu, "gl_deferred_near_redone");

    r.render(near, s);
    EXPECT_EQ(r.stats().readBacks, 0);
    EXPECT_IMAGES_CLOSE(r.readback(), cpuNear, kGlVsCpu, "gl_deferred_near");
    EXPECT_FALSE(r.stats().redone) << "sized from the redone frame";
}

TEST_F(GlTest, AGpusFramesNotReadAreNotDrawnAgain) {
    // The editor may draw frames nobody reads (a newer view supersedes them): none of them is checked or
    // drawn again, however short its lists, and the one whose image is used is whole.
    const ScopedEnv gpu("SPLATLAB_DRIVER_PROFILE", "gpu");
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(20), ramp());
    const SplatSettings s = tiled(Compositing::XRay);
    SplatRenderer r;
    r.setScene(scene);
    ImagePlane plane;
    for (double distance : {6.0, 3.0, 1.4}) {
        plane = makeImagePlane(Camera{.azimuthDeg = 35, .elevationDeg = 25, .distance = distance}, scene.centre,
                               scene.radius, 100, 84);
        r.render(plane, s);
        EXPECT_EQ(r.stats().readBacks, 0) << distance;
        EXPECT_FALSE(r.stats().redone) << distance;
    }
    EXPECT_IMAGES_CLOSE(r.readback(), renderReference(scene, plane, s), kGlVsCpu, "gl_deferred_unread");
}
