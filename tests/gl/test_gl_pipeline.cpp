// The GL pipeline beyond splat-every-sample: sheet buffers both ways with early termination, the
// filter-mode heatmap, GPU counters and patch modes, TF edits through bucket selection, point vs
// quad primitives. Every result is checked against the CPU oracle (tolerance: gl_fixture.h).
#include "gl_fixture.h"
#include "test_paths.h"

#include "renderer/errors.h"
#include "renderer/model/gradients.h"
#include "renderer/math/metrics.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/io/volume_io.h"

using namespace renderer;

namespace {

TransferFunction ramp(double opacity = 0.9) {
    return fromSharedPoints("test-ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.3, {0.3, 0.9, 0.4}, 0.2}, {1.0, {1.0, 0.8, 0.3}, opacity}});
}

struct Frame {
    SplatScene scene;
    ImagePlane plane;
};

Frame frame(const Volume& v, const TransferFunction& tf, const Camera& cam, int w, int h) {
    Frame f{buildSplatScene(v, tf), {}};
    f.plane = makeImagePlane(cam, f.scene.centre, f.scene.radius, w, h);
    return f;
}

} // namespace

TEST_F(GlTest, SheetBuffersMatchCpuBothWays) {
    // Perspective, rectilinear and orthographic; front to back with and without early termination.
    Volume v = makeMarschnerLobb(20);
    v.spacing = {1.0, 1.5, 1.0};
    for (bool ortho : {false, true}) {
        const Frame f = frame(v, ramp(), Camera{.azimuthDeg = 30, .elevationDeg = 20, .distance = 2.0, .orthographic = ortho},
                              96, 80);
        SplatRenderer r;
        r.setScene(f.scene);
        for (auto mode : {Compositing::SheetBackToFront, Compositing::SheetFrontToBack}) {
            for (double opaque : {1.0, 0.9}) {
                if (mode == Compositing::SheetBackToFront && opaque < 1.0) continue;
                SplatSettings s;
                s.compositing = mode;
                s.primitive = SplatSettings::Primitive::Raster;   // the rasteriser (tiles: test_gl_tiles.cpp)
                s.opaqueAlpha = opaque;
                s.density = 4.0;   // opaque enough that early termination has pixels to stop
                r.render(f.plane, s);
                const Image cpu = renderReference(f.scene, f.plane, s);
                EXPECT_GT(imageStats(cpu).meanAlpha, 0.2);
                EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu,
                                    std::string("gl_vs_cpu_") + compositingName(mode) + (ortho ? "_ortho" : "") +
                                        (opaque < 1.0 ? "_early" : ""));
            }
        }
    }
}

TEST_F(GlTest, EarlyTerminationChangesAPixelByLessThanWhatItSkips) {
    // A pixel stops once its alpha reaches opaqueAlpha, so what it misses is at most 1 - opaqueAlpha.
    const Frame f = frame(makeSphereShells(24, 8.0, 3.0), ramp(1.0), Camera{}, 64, 64);
    SplatRenderer r;
    r.setScene(f.scene);
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    s.primitive = SplatSettings::Primitive::Raster;   // the rasteriser (tiles: test_gl_tiles.cpp)
    s.density = 8.0;
    s.opaqueAlpha = 1.0;
    s.counters = true;
    r.render(f.plane, s);
    const Image full = r.readback();
    const uint64_t fullFragments = r.stats().fragments;
    s.opaqueAlpha = 0.95;
    r.render(f.plane, s);
    const Image early = r.readback();
    // Stopping at opaque pixels must save fill: fewer fragments pass.
    EXPECT_LT(r.stats().fragments, fullFragments);
    EXPECT_GT(r.stats().fragments, 0u);
    double worst = 0.0;
    size_t changed = 0;
    for (size_t i = 0; i < full.rgba.size(); ++i) {
        const double d = std::abs(double(full.rgba[i]) - early.rgba[i]);
        worst = std::max(worst, d);
        changed += d > 1e-6;
    }
    EXPECT_GT(changed, 0u) << "no pixel terminated: the test scene is not opaque enough";
    EXPECT_LE(worst, 0.05 + 1e-5);
}

TEST_F(GlTest, FrontToBackSplattingCullsHiddenSplatsLikeTheCpu) {
    // Splat-every-sample with early termination runs front to back, the exact reverse of its back-to-
    // front order; splats whose every tile was opaque at the last refresh are culled in the vertex
    // stage. Only early termination may change a pixel (by at most 1 - opaqueAlpha), and the GPU culls
    // exactly the splats the CPU oracle counts as hidden.
    const Frame f = frame(makeSphereShells(24, 8.0, 3.0), ramp(1.0), Camera{.azimuthDeg = 25, .elevationDeg = 10}, 64, 64);
    SplatRenderer r;
    r.setScene(f.scene);
    for (auto mode : {Compositing::SplatEverySample, Compositing::SheetFrontToBack}) {
        SCOPED_TRACE(compositingName(mode));
        SplatSettings s;
        s.compositing = mode;
        s.primitive = SplatSettings::Primitive::Raster;   // the rasteriser (tiles: test_gl_tiles.cpp)
        s.density = 8.0;
        s.counters = true;
        s.opaqueAlpha = 1.0;   // splat-every-sample: back to front
        r.render(f.plane, s);
        const Image full = r.readback();
        const uint64_t fullFragments = r.stats().fragments;

        s.opaqueAlpha = 0.95;
        s.opaqueRefreshSlices = 1000;   // never refreshed: nothing terminates, nothing is culled
        r.render(f.plane, s);
        EXPECT_EQ(r.stats().counters.culledOccluded, 0u);
        EXPECT_LT(compareImages(r.readback(), full).maxAbs, 1e-5);

        s.opaqueRefreshSlices = 3;
        r.render(f.plane, s);
        const Image early = r.readback();
        SplatCounters cpu;
        const Image cpuImage = renderReference(f.scene, f.plane, s, &cpu);
        expectCountersEqual(r.stats().counters, cpu);
        EXPECT_GT(cpu.culledOccluded, (cpu.drawn + cpu.culledOccluded) / 5) << "too few hidden splats to test";
        EXPECT_LT(r.stats().fragments, fullFragments / 2);
        EXPECT_IMAGES_CLOSE(early, cpuImage, kGlVsCpu, std::string("gl_vs_cpu_occlusion_") + compositingName(mode));
        const ImageError e = compareImages(early, full);
        EXPECT_GT(e.maxAbs, 1e-5);
        EXPECT_LE(e.maxAbs, 0.05 + 1e-5);
    }
}

TEST_F(GlTest, RasterisedSheetsCountTheSlicesTheySkipOffTheImage) {
    // A column of voxels along z in one corner (x, y < 5) and a ball in the middle; air is transparent
    // to the bucket. Close up the corner lies off the image in the nearer slices, so rasterised sheets skip
    // those slices' draws; with counters they draw them under an empty scissor, and the corner's
    // voxels are counted offscreen as the oracle counts them (before: not at all).
    Volume v;
    v.dims = {24, 24, 24};
    v.values.floats().assign(v.voxelCount(), 0.0f);
    for (int z = 0; z < 24; ++z)
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                const double r = glm::length(glm::dvec3(x, y, z) - glm::dvec3(11.5));
                const bool corner = x < 5 && y < 5;
                v.values.floats()[(size_t(z) * 24 + size_t(y)) * 24 + size_t(x)] = corner ? 0.8f : r < 6.0 ? 0.6f : 0.0f;
            }
    updateRange(v);
    const TransferFunction clearAir = fromSharedPoints("clear-air", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.2, {0.2, 0.4, 1.0}, 0.0},
                                                  {1.0, {1.0, 0.8, 0.3}, 0.9}});
    const Frame f = frame(v, clearAir, Camera{.azimuthDeg = 0, .elevationDeg = 89, .fovYDeg = 10}, 48, 48);
    ASSERT_EQ(chooseTraversal(f.plane).axis, 2) << "the corner column must cross every slice";
    SplatRenderer r;
    r.setScene(f.scene);
    for (auto mode : {Compositing::SheetBackToFront, Compositing::SheetFrontToBack}) {
        SCOPED_TRACE(compositingName(mode));
        SplatSettings s;
        s.compositing = mode;
        s.primitive = SplatSettings::Primitive::Raster;
        s.counters = true;
        r.render(f.plane, s);
        SplatCounters cpu;
        const Image cpuImage = renderReference(f.scene, f.plane, s, &cpu);
        EXPECT_GE(cpu.culledOffscreen, 8u * 25u) << "the corner column must lie off the image in several slices";
        expectCountersEqual(r.stats().counters, cpu);
        EXPECT_IMAGES_CLOSE(r.readback(), cpuImage, kGlVsCpu, std::string("gl_offscreen_slices_") + compositingName(mode));
    }
}

TEST_F(GlTest, HeatmapCountersAndPatchModesMatchCpu) {
    // A close, wide view of a deep volume: all three modes appear under the adaptive classifier.
    Volume v = makeSphereShells(20, 5.0, 2.0);
    v.spacing = {1.0, 1.0, 4.0};
    const Frame f = frame(v, ramp(), Camera{.azimuthDeg = 20, .elevationDeg = 15, .distance = 1.15, .fovYDeg = 70},
                          128, 128);
    SplatRenderer r;
    r.setScene(f.scene);
    Image shown;   // written last, for a person to look at: a machine that cannot write it still tests
    for (auto mode : {Compositing::SplatEverySample, Compositing::SheetFrontToBack, Compositing::XRay}) {
        SplatSettings s;
        s.filter = FilterMode::Adaptive;
        // Not a power of two: the GPU finds a voxel's patch by a float product, and rows of 7 patches
        // come back from the patch texture unpadded.
        s.patchSize = 3;
        s.cMin = 0.6;
        s.compositing = mode;
        s.primitive = SplatSettings::Primitive::Raster;   // the rasteriser (tiles: test_gl_tiles.cpp)
        s.heatmap = true;
        s.counters = true;
        r.render(f.plane, s);
        SplatCounters cpu;
        Image cpuHeat;
        renderReference(f.scene, f.plane, s, &cpu, &cpuHeat);
        ASSERT_TRUE(r.stats().hasCounters);
        expectCountersEqual(r.stats().counters, cpu);
        EXPECT_GT(cpu.drawnPerMode[0], 0u);
        EXPECT_GT(cpu.drawnPerMode[2], 0u);
        const Image heat = r.readbackHeatmap();
        EXPECT_IMAGES_CLOSE(heat, cpuHeat, kGlVsCpu, std::string("gl_vs_cpu_heatmap_") + compositingName(mode));
        // The shares split the pixel's alpha: r + g + b == a.
        for (size_t px = 0; px < heat.rgba.size(); px += 4)
            ASSERT_NEAR(heat.rgba[px] + heat.rgba[px + 1] + heat.rgba[px + 2], heat.rgba[px + 3], 1e-5);
        if (mode == Compositing::SplatEverySample) {
            EXPECT_EQ(r.patchModes(f.plane, s), patchModes(f.scene, f.plane, s));
            shown = heat;
        }
    }
    writeImage(shown, testing_support::testOutputDir() / "heatmap_adaptive.png");
}

TEST_F(GlTest, TfEditUploadsOnlyTheLutAndSelectsBuckets) {
    const Volume v = loadVolume(testing_support::assetDir() / "volumes" / "headsq.nhdr");
    SplatScene scene = buildSplatScene(v, builtinPreset("ct-skin-bone"));
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, 96, 96);
    SplatRenderer r;
    r.setScene(scene);
    EXPECT_GT(r.stats().uploadBytes, scene.classes.size() * 2);
    // GPU bytes of one axis's lists: 2 per listed voxel (whole words), 16 per run and 4 per slice (where
    // its runs start).
    auto listBytes = [&](int axis) {
        const AxisLists& l = scene.lists[size_t(axis)];
        return uint64_t((l.entries().size() + 1) / 2 * 4 + l.runs.size() * 16 + l.sliceRuns.size() * 4);
    };
    // The first frame puts its axis's lists on the GPU; the next frames upload uniforms only.
    const uint64_t setUp = r.stats().uploadBytes;
    r.render(plane, SplatSettings{});
    EXPECT_EQ(r.stats().uploadBytes, listBytes(chooseTraversal(plane).axis));
    EXPECT_EQ(r.stats().frameUploadBytes, setUp + listBytes(chooseTraversal(plane).axis));   // the whole scene
    r.render(plane, SplatSettings{});
    EXPECT_EQ(r.stats().uploadBytes, 0u);
    EXPECT_EQ(r.stats().frameUploadBytes, 0u);
    // GPU bytes: classes 2 a voxel, the LUT (and the gradient factors after it), the largest axis's lists (only the view's axis is on the
    // GPU), one command array of 32 bytes a run of the axis with the most (points and quads), and one
    // word standing in for the gradients (3 bytes a voxel once the scene has them).
    uint64_t expected = scene.classes.size() * 2 + (kLutSize + kGradientBins) * 16 + 4;
    size_t mostRuns = 0;
    uint64_t largest = 0;
    for (int axis = 0; axis < 3; ++axis) {
        largest = std::max(largest, listBytes(axis));
        mostRuns = std::max(mostRuns, scene.lists[size_t(axis)].runs.size());
    }
    expected += largest + mostRuns * 32;
    EXPECT_EQ(r.sceneBytes(), expected);

    for (const char* preset : {"ct-bone", "grey-ramp", "fire"}) {
        setTransferFunction(scene, builtinPreset(preset));
        r.setLut(tfTables(scene));
        EXPECT_EQ(r.stats().uploadBytes, kLutSize * sizeof(glm::vec4)) << preset;
        r.render(plane, SplatSettings{});
        EXPECT_EQ(r.stats().uploadBytes, 0u);
        EXPECT_EQ(r.stats().frameUploadBytes, kLutSize * sizeof(glm::vec4)) << preset;   // the edit's frame
        EXPECT_IMAGES_CLOSE(r.readback(), renderReference(scene, plane, SplatSettings{}), kGlVsCpu,
                            std::string("gl_vs_cpu_tf_") + preset);
    }
    // Turning the view to another major axis uploads that axis's lists once, and draws it right.
    std::set<int> axes;
    int previous = chooseTraversal(plane).axis;
    for (const Camera& camera : {Camera{.azimuthDeg = 90}, Camera{.elevationDeg = 80}, Camera{}}) {
        const ImagePlane turned = makeImagePlane(camera, scene.centre, scene.radius, 96, 96);
        const int axis = chooseTraversal(turned).axis;
        ASSERT_NE(axis, previous);
        previous = axis;
        axes.insert(axis);
        r.render(turned, SplatSettings{});
        EXPECT_EQ(r.stats().uploadBytes, listBytes(axis)) << "axis " << axis;
        r.render(turned, SplatSettings{});
        EXPECT_EQ(r.stats().uploadBytes, 0u) << "axis " << axis;
        EXPECT_IMAGES_CLOSE(r.readback(), renderReference(scene, turned, SplatSettings{}), kGlVsCpu,
                            "gl_vs_cpu_axis_" + std::to_string(axis));
    }
    EXPECT_EQ(axes.size(), 3u);
    EXPECT_EQ(r.sceneBytes(), expected);
}

TEST_F(GlTest, PointsQuadsAndAllBucketsDrawTheSameImage) {
    const Frame f = frame(makeMarschnerLobb(16), ramp(), Camera{.azimuthDeg = 40, .elevationDeg = 30}, 64, 64);
    SplatRenderer r;
    r.setScene(f.scene);
    const Image cpu = renderReference(f.scene, f.plane, SplatSettings{});
    SplatSettings s;
    for (auto primitive : {SplatSettings::Primitive::Points, SplatSettings::Primitive::Quads}) {
        s.primitive = primitive;
        r.render(f.plane, s);
        EXPECT_EQ(r.stats().pointSlices > 0, primitive == SplatSettings::Primitive::Points);
        EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu,
                            primitive == SplatSettings::Primitive::Points ? "gl_points" : "gl_quads");
    }
    s.primitive = SplatSettings::Primitive::Auto;
    s.drawAllBuckets = true;
    s.counters = true;
    r.render(f.plane, s);
    EXPECT_EQ(r.stats().splatsDrawn, f.scene.classes.size());
    EXPECT_EQ(r.stats().counters.visible, f.scene.classes.size());
    EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, "gl_all_buckets");
}

TEST_F(GlTest, AutoPrimitiveFallsBackToQuadsForHugeFootprints) {
    // From inside the volume, footprints near the eye exceed any point size.
    const Frame f = frame(makeMarschnerLobb(16), ramp(), Camera{.distance = 0.3, .fovYDeg = 90}, 64, 64);
    SplatRenderer r;
    r.setScene(f.scene);
    r.render(f.plane, SplatSettings{});
    EXPECT_GT(r.stats().quadSlices, 0);
    EXPECT_IMAGES_CLOSE(r.readback(), renderReference(f.scene, f.plane, SplatSettings{}), kGlVsCpu, "gl_inside");
    SplatSettings s;
    s.primitive = SplatSettings::Primitive::Points;
    EXPECT_THROW(r.render(f.plane, s), RenderError);
    // The refused frame leaves no GL query running: the next frame renders without a GL error.
    EXPECT_NO_THROW(r.render(f.plane, SplatSettings{}));
}

TEST_F(GlTest, CloseViewsDrawFarSlicesAsPointsAndNearOnesAsQuads) {
    // Close up, the near slices' footprints outgrow any point size while the far slices' still fit:
    // each slice takes its own primitive, in every rasterised draw order (front to back in groups of
    // slices, back to front in one pass, sheets slice by slice), with the oracle's image and counters.
    const Frame f = frame(makeMarschnerLobb(24), ramp(), Camera{.azimuthDeg = 20, .elevationDeg = 15, .distance = 0.5, .fovYDeg = 90},
                          64, 64);
    SplatRenderer r;
    r.setScene(f.scene);
    struct Case {
        Compositing mode;
        double opaqueAlpha;
    };
    for (const Case c : {Case{Compositing::SplatEverySample, 0.998}, Case{Compositing::SplatEverySample, 1.0},
                         Case{Compositing::SheetBackToFront, 0.998}, Case{Compositing::SheetFrontToBack, 0.998}}) {
        SCOPED_TRACE(std::string(compositingName(c.mode)) + " opaque alpha " + std::to_string(c.opaqueAlpha));
        SplatSettings s;
        s.compositing = c.mode;
        s.opaqueAlpha = c.opaqueAlpha;
        s.primitive = SplatSettings::Primitive::Raster;
        s.counters = true;
        r.render(f.plane, s);
        EXPECT_GT(r.stats().pointSlices, 0);
        EXPECT_GT(r.stats().quadSlices, 0);
        EXPECT_EQ(r.stats().pointSlices + r.stats().quadSlices, 24);   // every slice holds visible voxels
        EXPECT_EQ(primitiveName(r.stats()),
                  "points and quads (quads in " + std::to_string(r.stats().quadSlices) + " of 24 slices)");
        const Image mixed = r.readback();
        SplatCounters cpu;
        EXPECT_IMAGES_CLOSE(mixed, renderReference(f.scene, f.plane, s, &cpu), kGlVsCpu,
                            std::string("gl_points_and_quads_") + compositingName(c.mode));
        expectCountersEqual(r.stats().counters, cpu);

        s.primitive = SplatSettings::Primitive::Quads;
        r.render(f.plane, s);
        EXPECT_EQ(r.stats().pointSlices, 0);
        EXPECT_LT(compareImages(r.readback(), mixed).maxAbs, 1e-6);
        s.primitive = SplatSettings::Primitive::Points;
        EXPECT_THROW(r.render(f.plane, s), RenderError);
    }
}

TEST_F(GlTest, ElongatedFootprintsTakeQuadsWherePointsWouldWasteFill) {
    // Voxels four times as wide as deep: a point sprite, square around the footprint's longer side,
    // would cover three times the quad's box. Every footprint fits a point either way; auto draws quads
    // for the flat voxels, points for the same volume with cubic voxels, both with the oracle's image.
    for (const glm::dvec3 spacing : {glm::dvec3(4.0, 4.0, 1.0), glm::dvec3(2.0)}) {
        SCOPED_TRACE(spacing.x > spacing.z ? "flat voxels" : "cubic voxels");
        Volume v = makeMarschnerLobb(16);
        v.spacing = spacing;
        const Frame f = frame(v, ramp(), Camera{.azimuthDeg = 10, .elevationDeg = 10}, 128, 128);
        SplatRenderer r;
        r.setScene(f.scene);
        r.render(f.plane, SplatSettings{});
        const bool flat = spacing.x > spacing.z;
        EXPECT_EQ(r.stats().pointSlices > 0, !flat);
        EXPECT_EQ(r.stats().quadSlices > 0, flat);
        EXPECT_IMAGES_CLOSE(r.readback(), renderReference(f.scene, f.plane, SplatSettings{}), kGlVsCpu,
                            flat ? "gl_flat_voxels_quads" : "gl_cubic_voxels_points");
        SplatSettings points;
        points.primitive = SplatSettings::Primitive::Points;
        EXPECT_NO_THROW(r.render(f.plane, points)) << "the footprints must fit points";
    }
}

TEST_F(GlTest, RealScansStayWithinEightGpuBytesPerVoxel) {
    // Every scan in the shared folder, with the gradients shading and surface splats need: dense runs
    // keep air out of the lists, and only the view's axis's lists are on the GPU.
    SPLATLAB_REQUIRE_SHARED_DATA(dir);
#if defined(__SANITIZE_ADDRESS__)
    // Under AddressSanitizer the 256^3 scans take nearly 3 minutes to read and grade, a tenth of CI; the
    // small ones walk the same code (the release run checks every scan's bytes).
    const std::vector<const char*> names{"neghip", "hydrogen", "headsq", "head_mr", "mni_avg152t1"};
#else
    const std::vector<const char*> names{"bonsai",  "engine",   "aneurism", "tooth",  "lidc2_chest_ct", "neghip",
                                         "hydrogen", "headsq", "head_mr",  "embryo", "mni_avg152t1"};
#endif
    for (const char* name : names) {
        const auto path = dir / (std::string(name) + (std::string(name) == "tooth" ? ".nrrd" : ".nhdr"));
        const Volume volume = loadVolume(path);
        SplatScene scene = buildSplatScene(volume, builtinPreset("ct-bone"));
        addGradients(scene, *computeGradients(volume));
        SplatRenderer r;
        r.setScene(scene);
        double largest = 0.0;
        for (const Camera& camera : {Camera{}, Camera{.azimuthDeg = 90}, Camera{.elevationDeg = 80}}) {
            r.render(makeImagePlane(camera, scene.centre, scene.radius, 32, 32), SplatSettings{});
            largest = std::max(largest, double(r.sceneBytes()) / double(scene.classes.size()));
        }
        std::cout << "[ memory   ] " << name << ": " << largest << " GPU bytes per voxel\n";
        EXPECT_LE(largest, 8.0) << name;
    }
}

namespace {

SplatScene withGradients(const Volume& v, const TransferFunction& tf) {
    SplatScene scene = buildSplatScene(v, tf);
    addGradients(scene, *computeGradients(v));
    return scene;
}

} // namespace

TEST_F(GlTest, ShadingPerSplatAndPerFragmentMatchCpu) {
    const Volume v = makeSphereShells(24, 8.0, 2.5);
    const SplatScene scene = withGradients(v, ramp());
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 30, .elevationDeg = 20, .fovYDeg = 50}, scene.centre,
                                            scene.radius, 96, 96);
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s;
    const Image unshaded = renderReference(scene, plane, s);
    for (auto shading : {SplatSettings::Shading::PerSplat, SplatSettings::Shading::PerFragment}) {
        s.shading = shading;
        r.render(plane, s);
        const Image cpu = renderReference(scene, plane, s);
        // Shading must change the image (a test of something), and GL must agree with the CPU.
        EXPECT_GT(compareImages(cpu, unshaded).maxAbs, 0.05);
        EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu,
                            shading == SplatSettings::Shading::PerSplat ? "gl_shaded_splat" : "gl_shaded_fragment");
    }
    const Image shaded = r.readback();
    SplatScene bare = buildSplatScene(v, ramp());
    r.setScene(bare);
    EXPECT_THROW(r.render(plane, s), RenderError);   // shading without gradients: a clear error
    EXPECT_THROW(renderReference(bare, plane, s), RenderError);
    writeImage(shaded, testing_support::testOutputDir() / "shells_shaded.png");   // last: see the heatmap test
}

TEST_F(GlTest, SurfaceSplatsMatchCpuAndStayFiniteEdgeOn) {
    // A slab seen face-on, obliquely and exactly edge-on: flattened kernels in every filter mode. Its
    // profile across z is a tent (0, .25, .5, .75, 1, .75, ...), so visible voxels have a gradient.
    Volume v;
    v.dims = {24, 24, 9};
    v.values.floats().assign(v.voxelCount(), 0.0f);
    for (int z = 0; z < 9; ++z)
        for (int i = 0; i < 24 * 24; ++i) v.values.floats()[size_t(z) * 24 * 24 + i] = float(1.0 - std::abs(z - 4) / 4.0);
    v.range = {0.0f, 1.0f};
    const SplatScene scene = withGradients(v, ramp());
    SplatRenderer r;
    r.setScene(scene);
    for (double elevation : {89.0, 40.0, 0.0}) {
        const ImagePlane plane =
            makeImagePlane(Camera{.azimuthDeg = 0, .elevationDeg = elevation, .distance = 1.6}, scene.centre,
                           scene.radius, 64, 64);
        for (auto filter : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa, FilterMode::Adaptive}) {
            SplatSettings s;
            s.filter = filter;
            s.surfaceFlatten = 20.0;
            s.surfaceGradient = 0.05;
            s.counters = true;
            SplatCounters cpuCounters;
            const Image cpu = renderReference(scene, plane, s, &cpuCounters);
            r.render(plane, s);
            const Image gl = r.readback();
            const std::string name = "gl_surface_el" + std::to_string(int(elevation)) + "_" + filterModeName(filter);
            EXPECT_TRUE(imageStats(gl).finite) << name;
            EXPECT_EQ(cpuCounters.culledHuge, 0u) << name;
            EXPECT_EQ(r.stats().counters.drawn, cpuCounters.drawn) << name;
            EXPECT_IMAGES_CLOSE(gl, cpu, kGlVsCpu, name);
            // Flattening must show where it can: not in low-pass footprints (V_h alone), and barely
            // face-on (the kernel is flattened along the view, which does not project).
            if (elevation == 40.0 && filter != FilterMode::LowPass) {
                SplatSettings volumeKernels = s;
                volumeKernels.surfaceFlatten = 1.0;
                EXPECT_GT(compareImages(cpu, renderReference(scene, plane, volumeKernels)).maxAbs, 1e-3) << name;
            }
        }
    }
}

TEST_F(GlTest, HysteresisKeepsPatchFiltersAcrossASmallCameraMoveLikeTheCpu) {
    // Two frames a little apart. With hysteresis the GPU's patch modes of frame 2 equal the CPU's given
    // frame 1's, fewer patches change filter than without, and the images agree.
    Volume v = makeSphereShells(20, 5.0, 2.0);
    v.spacing = {1.0, 1.0, 4.0};
    const SplatScene scene = buildSplatScene(v, ramp());
    const Camera first{.azimuthDeg = 20, .elevationDeg = 15, .distance = 1.15, .fovYDeg = 70};
    Camera second = first;
    second.distance = 1.4;
    const ImagePlane a = makeImagePlane(first, scene.centre, scene.radius, 128, 128);
    const ImagePlane b = makeImagePlane(second, scene.centre, scene.radius, 128, 128);
    SplatSettings s;
    s.filter = FilterMode::Adaptive;
    s.patchSize = 4;
    s.cMin = 0.6;
    auto changed = [](const std::vector<uint8_t>& x, const std::vector<uint8_t>& y) {
        size_t n = 0;
        for (size_t i = 0; i < x.size(); ++i) n += x[i] != y[i];
        return n;
    };
    const size_t withoutHysteresis = changed(patchModes(scene, a, s), patchModes(scene, b, s));
    s.hysteresis = 0.25;
    SplatRenderer r;
    r.setScene(scene);
    r.render(a, s);   // frame 1: no previous frame
    const std::vector<uint8_t> cpuFirst = patchModes(scene, a, s);
    r.render(b, s);   // frame 2 remembers frame 1
    const Image gl = r.readback();
    const std::vector<uint8_t> cpuSecond = patchModes(scene, b, s, &cpuFirst);
    EXPECT_EQ(r.patchModes(b, s), patchModes(scene, b, s, &cpuSecond));   // a third classification
    std::printf("[ patches  ] changed filter: %zu without hysteresis, %zu with h = 0.25 (of %zu)\n",
                withoutHysteresis, changed(cpuFirst, cpuSecond), cpuFirst.size());
    EXPECT_GT(withoutHysteresis, 0u);
    EXPECT_LT(changed(cpuFirst, cpuSecond), withoutHysteresis);
    EXPECT_IMAGES_CLOSE(gl, renderReference(scene, b, s, nullptr, nullptr, &cpuFirst), kGlVsCpu, "gl_hysteresis");
}

TEST_F(GlTest, AdaptiveFramesTheViewDecidesRunThatFilterLikeTheCpu) {
    // At 4 radii every patch is EWA, at 40 low-pass (uniformAdaptiveFilter): those frames run that
    // filter's code and set the patches to it without their pass. Image, heatmap and counters stay the
    // CPU's. At 11 the view does not decide; hysteresis keeps every patch low-pass from the frame
    // before, as from the pass's modes. Up close, patches differ.
    const SplatScene scene = buildSplatScene(makeSphereShells(20, 5.0, 2.0), ramp());
    SplatSettings s;
    s.filter = FilterMode::Adaptive;
    s.patchSize = 4;
    s.cMin = 0.6;
    s.hysteresis = 0.25;
    s.heatmap = true;
    s.counters = true;
    SplatRenderer r;
    r.setScene(scene);
    const std::vector<uint8_t>* previous = nullptr;
    std::vector<uint8_t> cpuModes;
    using enum FilterMode;
    struct View {
        double distance;
        FilterMode decided, drawn;   // drawn: the one filter every splat took, else Adaptive
    };
    for (const View& view : {View{4.0, Ewa, Ewa}, View{40.0, LowPass, LowPass}, View{11.0, Adaptive, LowPass},
                             View{1.15, Adaptive, Adaptive}}) {
        const ImagePlane plane =
            makeImagePlane({.azimuthDeg = 20, .elevationDeg = 15, .distance = view.distance, .fovYDeg = 70},
                           scene.centre, scene.radius, 96, 96);
        r.render(plane, s);
        EXPECT_EQ(r.stats().adaptiveAs, view.decided) << view.distance;
        SplatCounters cpu;
        Image cpuHeat;
        const Image image = renderReference(scene, plane, s, &cpu, &cpuHeat, previous);
        const std::string name = "gl_decided_" + std::to_string(int(view.distance));
        EXPECT_IMAGES_CLOSE(r.readback(), image, kGlVsCpu, name);
        EXPECT_IMAGES_CLOSE(r.readbackHeatmap(), cpuHeat, kGlVsCpu, name + "_heatmap");
        expectCountersEqual(r.stats().counters, cpu);
        if (view.drawn != Adaptive) {
            EXPECT_EQ(cpu.drawnPerMode[int(view.drawn)], cpu.drawn) << view.distance;
        } else {   // a shortcut, and EWA where corners disagree
            EXPECT_GT(cpu.drawnPerMode[0], 0u);
            EXPECT_GT(cpu.drawnPerMode[2], 0u);
        }
        cpuModes = patchModes(scene, plane, s, previous);
        previous = &cpuModes;
    }
}

// An editor drops a frame a newer edit superseded: the interrupt is asked between chunks (tiled) and
// between slices (rasterised), the frame stops at the first yes, and the next frame is whole again.
TEST_F(GlTest, AnInterruptedFrameStopsAtItsNextChunkAndTheNextFrameIsWhole) {
    const Frame f = frame(makeMarschnerLobb(24), ramp(), Camera{.azimuthDeg = 40, .elevationDeg = 30}, 64, 64);
    SplatRenderer r;
    r.setScene(f.scene);
    r.setListChunkSlices(4);   // several chunks in the tiled frames
    for (Compositing c : {Compositing::SheetBackToFront, Compositing::SheetFrontToBack, Compositing::SplatEverySample}) {
        for (auto primitive : {SplatSettings::Primitive::Tiles, SplatSettings::Primitive::Quads}) {
            SCOPED_TRACE(std::string(compositingName(c)) + (primitive == SplatSettings::Primitive::Tiles ? " tiles" : " quads"));
            if (c == Compositing::SplatEverySample && primitive == SplatSettings::Primitive::Tiles) continue;
            SplatSettings s;
            s.compositing = c;
            s.primitive = primitive;
            int asked = 0;
            r.setInterrupt([&] { return ++asked >= 2; });
            EXPECT_THROW(r.render(f.plane, s), Cancelled);
            EXPECT_EQ(asked, 2) << "asked again after it said stop";
            r.setInterrupt({});
            r.render(f.plane, s);
            EXPECT_IMAGES_CLOSE(r.readback(), renderReference(f.scene, f.plane, s), kGlVsCpu, "gl_after_interrupt");
        }
    }
}
