// Tiled splatting (SplatSettings::Primitive::Tiles): compute passes bin the splats to 8x8 pixel
// tiles and composite every pixel in registers. Each sheet and X-ray mode, filter, heatmap, shading
// and early termination against the CPU oracle (tolerance: gl_fixture.h), counters included.
#include "gl_fixture.h"

#include "renderer/math/classifier.h"
#include "renderer/errors.h"
#include "renderer/model/gradients.h"
#include "renderer/math/metrics.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/gl/splat_renderer.h"

#include <algorithm>

using namespace renderer;

namespace {

TransferFunction ramp(double opacity = 0.9) {
    return fromSharedPoints("test-ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.3, {0.3, 0.9, 0.4}, 0.2}, {1.0, {1.0, 0.8, 0.3}, opacity}});
}

SplatSettings tiled(Compositing mode) {
    SplatSettings s;
    s.compositing = mode;
    s.primitive = SplatSettings::Primitive::Tiles;
    return s;
}

// The frame `r` just rendered with `s` (heatmap and counters on) against the CPU oracle's: image,
// heatmap and counters.
void expectFrameMatchesCpu(SplatRenderer& r, const SplatScene& scene, const ImagePlane& plane,
                           const SplatSettings& s, const std::string& name) {
    SplatCounters cpuCounters;
    Image cpuHeat;
    const Image cpu = renderReference(scene, plane, s, &cpuCounters, &cpuHeat);
    EXPECT_GT(imageStats(cpu).meanAlpha, 0.2);
    EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, name);
    EXPECT_IMAGES_CLOSE(r.readbackHeatmap(), cpuHeat, kGlVsCpu, name + "_heatmap");
    expectCountersEqual(r.stats().counters, cpuCounters);
}

struct SceneView {
    SplatScene scene;
    ImagePlane plane;
};

// 96 slices seen along z, by front-to-back rank: 36 empty; a wall over the left half (x < 20); 24 of
// faint fill (never opaque); a wall over the right half; 12 empty; 16 of fill. Nothing is opaque after
// the first two chunks (8 slices each, kTileChunkSlices), so the next ones double (nextOcclusionChunk()):
// ranks 16-31, then 32-63, which holds the left wall and the fill behind it, so none of that fill is
// culled; then chunks of 8: the last fill is culled against both walls. Chunks of 8 throughout, or
// chunks that stop doubling at 16, cull other splats (23.2 k and 15.1 k against 13.4 k): the counters differ.
SceneView wallsAndFill() {
    const glm::dvec3 centre(19.5, 19.5, 47.5);
    const double radius = std::sqrt(2.0 * 19.5 * 19.5 + 47.5 * 47.5);
    SceneView w{.scene = {}, .plane = makeImagePlane(Camera{.azimuthDeg = 10, .elevationDeg = 75}, centre, radius, 128, 128)};
    const Traversal order = chooseTraversal(w.plane);
    EXPECT_EQ(order.axis, 2);
    Volume v;
    v.dims = {40, 40, 96};
    v.values.floats().assign(v.voxelCount(), 0.0f);
    for (int rank = 0; rank < 96; ++rank) {
        const int z = order.descending ? rank : 95 - rank;   // front to back reverses the traversal
        for (int y = 0; y < 40; ++y)
            for (int x = 0; x < 40; ++x) {
                const bool wall = (rank >= 36 && rank < 40 && x < 20) || (rank >= 64 && rank < 68 && x >= 20);
                const float fill = rank >= 40 && rank < 64 ? 0.51f : rank >= 80 ? 0.6f : 0.0f;
                v.values.floats()[(size_t(z) * 40 + size_t(y)) * 40 + size_t(x)] = wall ? 1.0f : fill;
            }
    }
    updateRange(v);
    const TransferFunction step = fromSharedPoints("step", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.5, {0.2, 0.4, 1.0}, 0.0}, {1.0, {1.0, 0.8, 0.3}, 1.0}});
    w.scene = buildSplatScene(v, step);
    EXPECT_LT(glm::length(w.scene.centre - centre), 1e-9) << "the plane must frame the scene";
    EXPECT_NEAR(w.scene.radius, radius, 1e-9);
    return w;
}

// A Marschner-Lobb volume from far away: reconstruction-only footprints there have a sigma of 0.06 px.
SceneView farMarschnerLobb() {
    SceneView v{.scene = buildSplatScene(makeMarschnerLobb(40), ramp()), .plane = {}};
    v.plane = makeImagePlane(Camera{.azimuthDeg = 20, .elevationDeg = 15, .distance = 24}, v.scene.centre,
                             v.scene.radius, 48, 40);
    return v;
}

} // namespace

TEST_F(GlTest, TiledSplattingMatchesCpuInEverySheetAndXRayMode) {
    // Close up on a rectilinear volume: splats straddle the image border, and 100x84 leaves partial
    // tiles on the right and bottom. Perspective and orthographic, full EWA and adaptive, heatmap on.
    Volume v = makeMarschnerLobb(20);
    v.spacing = {1.0, 1.5, 1.0};
    const SplatScene scene = buildSplatScene(v, ramp());
    SplatRenderer r;
    r.setScene(scene);
    for (bool ortho : {false, true}) {
        const ImagePlane plane = makeImagePlane(
            Camera{.azimuthDeg = 35, .elevationDeg = 25, .distance = 1.4, .orthographic = ortho}, scene.centre,
            scene.radius, 100, 84);
        for (auto mode : {Compositing::SheetBackToFront, Compositing::SheetFrontToBack, Compositing::XRay})
            for (auto filter : {FilterMode::Ewa, FilterMode::Adaptive}) {
                const std::string name = std::string("gl_tiles_") + compositingName(mode) + "_" +
                                         filterModeName(filter) + (ortho ? "_ortho" : "");
                SCOPED_TRACE(name);
                SplatSettings s = tiled(mode);
                s.filter = filter;
                s.density = 4.0;   // front to back: opaque enough that early termination stops pixels
                s.heatmap = true;
                s.counters = true;
                r.render(plane, s);
                expectFrameMatchesCpu(r, scene, plane, s, name);
                EXPECT_GT(r.stats().tileEntries, r.stats().counters.drawn) << "footprints span several tiles";
            }
    }
}

TEST_F(GlTest, TiledSplattingStopsAtOpaquePixelsLikeTheCpu) {
    // Front to back, refreshed every slice (auto): only early termination changes a pixel, by at most
    // 1 - opaqueAlpha. The 24 slices go in several chunks (occlusionSlices): each later one is binned
    // against the tiles the ones before made opaque, so splats are culled and tiles lose entries; the
    // CPU agrees.
    const SplatScene scene = buildSplatScene(makeSphereShells(24, 8.0, 3.0), ramp(1.0));
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 25, .elevationDeg = 10}, scene.centre, scene.radius, 72, 64);
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s = tiled(Compositing::SheetFrontToBack);
    s.density = 8.0;
    s.counters = true;
    s.opaqueAlpha = 1.0;
    r.render(plane, s);
    const Image full = r.readback();
    const uint64_t allEntries = r.stats().tileEntries;
    s.opaqueAlpha = 0.95;
    ASSERT_EQ(opaqueRefreshSlices(s), 1);
    ASSERT_LE(occlusionSlices(s), 12) << "the 24 slices must go in two chunks or more";
    r.render(plane, s);
    const Image early = r.readback();
    SplatCounters cpu;
    EXPECT_IMAGES_CLOSE(early, renderReference(scene, plane, s, &cpu), kGlVsCpu, "gl_tiles_early_termination");
    expectCountersEqual(r.stats().counters, cpu);
    EXPECT_GT(cpu.culledOccluded, 0u);
    const uint64_t culledEntries = r.stats().tileEntries;
    EXPECT_LT(culledEntries, allEntries - cpu.culledOccluded) << "hidden splats and opaque tiles take no entries";
    // The measurement baseline: no culling gives the same image, with every splat drawn and binned.
    s.occlusionCulling = false;
    r.render(plane, s);
    EXPECT_IMAGES_CLOSE(r.readback(), early, kGlVsCpu, "gl_tiles_without_occlusion_culling");
    SplatCounters unculled;
    renderReference(scene, plane, s, &unculled);
    expectCountersEqual(r.stats().counters, unculled);
    EXPECT_EQ(unculled.culledOccluded, 0u);
    EXPECT_EQ(unculled.drawn, cpu.drawn + cpu.culledOccluded);
    EXPECT_EQ(r.stats().tileEntries, allEntries);
    s.occlusionCulling = true;
    const ImageError e = compareImages(early, full);
    EXPECT_GT(e.maxAbs, 1e-5) << "no pixel terminated: the test scene is not opaque enough";
    EXPECT_LE(e.maxAbs, 0.05 + 1e-5);
    // The rasteriser's refresh interval gives the rasteriser's image.
    s.opaqueRefreshSlices = 3;
    r.render(plane, s);
    const Image tiles3 = r.readback();
    EXPECT_TRUE(r.stats().tiles);
    s.primitive = SplatSettings::Primitive::Quads;
    r.render(plane, s);
    EXPECT_FALSE(r.stats().tiles);
    EXPECT_IMAGES_CLOSE(tiles3, r.readback(), kGlVsCpu, "gl_tiles_vs_quads_refresh_3");
}

TEST_F(GlTest, TiledSplattingRefreshesAfterSlicesWithoutSplatsLikeTheCpu) {
    // Seen along z: slices 0, 4, 19 and 23 hold splats (ranks 0 and 4 from either end), the rest are
    // exactly transparent, and a tile skips slices it has no splats from. Refreshing every 3 slices,
    // the boundary at rank 3 falls on a skipped slice: the tile must refresh before rank 4, as the CPU
    // does at the boundary (dropping that carry-over fails here). Every 4: the boundary is rank 4.
    Volume v;
    v.dims = {16, 16, 24};
    v.values.floats().assign(v.voxelCount(), 0.0f);
    for (int z : {0, 4, 19, 23})
        for (int i = 0; i < v.dims.x * v.dims.y; ++i) v.values.floats()[size_t(z) * 256 + size_t(i)] = 1.0f;
    updateRange(v);
    // Zero exactly transparent (the ramp's first class keeps a trace of opacity): empty slices.
    const TransferFunction step = fromSharedPoints("step", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.5, {0.2, 0.4, 1.0}, 0.0}, {1.0, {1.0, 0.8, 0.3}, 1.0}});
    const SplatScene scene = buildSplatScene(v, step);
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 10, .elevationDeg = 75}, scene.centre, scene.radius, 64, 64);
    ASSERT_EQ(chooseTraversal(plane).axis, 2);
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s = tiled(Compositing::SheetFrontToBack);
    s.density = 4.0;
    s.opaqueAlpha = 0.5;   // the wall takes pixels past it: what they would still take shows
    s.opaqueRefreshSlices = 1000;
    r.render(plane, s);
    const Image never = r.readback();
    for (int refresh : {3, 4}) {
        SCOPED_TRACE("refresh every " + std::to_string(refresh));
        s.opaqueRefreshSlices = refresh;
        r.render(plane, s);
        const Image tiles = r.readback();
        EXPECT_IMAGES_CLOSE(tiles, renderReference(scene, plane, s), kGlVsCpu, "gl_tiles_refresh_gap");
        EXPECT_GT(compareImages(tiles, never).maxAbs, 0.05) << "the wall must stop pixels";
    }
}

TEST_F(GlTest, TiledSplattingShadesAndFlattensSurfacesLikeTheCpu) {
    const Volume v = makeSphereShells(20, 6.0, 2.0);
    SplatScene scene = buildSplatScene(v, ramp());
    addGradients(scene, *computeGradients(v));
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 40, .elevationDeg = 30, .distance = 2.0}, scene.centre,
                                            scene.radius, 80, 72);
    SplatRenderer r;
    r.setScene(scene);
    for (auto shading : {SplatSettings::Shading::PerSplat, SplatSettings::Shading::PerFragment})
        for (double flatten : {1.0, 8.0}) {
            SCOPED_TRACE(std::to_string(int(shading)) + " flatten " + std::to_string(flatten));
            SplatSettings s = tiled(Compositing::SheetBackToFront);
            s.shading = shading;
            s.surfaceFlatten = flatten;
            r.render(plane, s);
            const Image cpu = renderReference(scene, plane, s);
            EXPECT_GT(imageStats(cpu).meanAlpha, 0.05);
            EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, "gl_tiles_shaded");
        }
}

TEST_F(GlTest, TiledSplattingCoversImagesOfManyTilesAndEmptyFrames) {
    // 600x560 is 75x70 tiles: the tile offsets' single workgroup scans more than one tile per lane, and
    // with over 80 % of the pixels covered more than 4,096 tiles have entries, so the composite's
    // indirect grid (4,096 tiles a row) takes a second row.
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(16), ramp());
    const ImagePlane plane = makeImagePlane(Camera{.distance = 1.2}, scene.centre, scene.radius, 600, 560);
    SplatRenderer r;
    r.setScene(scene);
    const SplatSettings s = tiled(Compositing::SheetFrontToBack);
    r.render(plane, s);
    const Image cpu = renderReference(scene, plane, s);
    EXPECT_GT(imageStats(cpu).coveredFraction, 0.8);
    EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, "gl_tiles_many");
    // A fully transparent TF: nothing is binned, the image is cleared.
    const TransferFunction clear = fromSharedPoints("clear", {{0.0, {1.0, 1.0, 1.0}, 0.0}, {1.0, {1.0, 1.0, 1.0}, 0.0}});
    SplatScene empty = scene;
    setTransferFunction(empty, clear);
    r.setLut(tfTables(empty));
    r.render(plane, s);
    EXPECT_EQ(r.stats().tileEntries, 0u);
    EXPECT_EQ(imageStats(r.readback()).coveredFraction, 0.0);
}

// llvmpipe ends a shader invocation's loops once they have run 65535 iterations together, silently.
// A tile's composite loops over its entries, so a tile crowded with the splats of minified slices lost
// them (bonsai in 256x256 from distance 8: errors up to 0.78 in X-ray), and a long run of one slice's
// voxels lost splats in the record pass. Each frame here matches the CPU oracle, or tiles refuse it with
// the reason and auto rasterises it: never a wrong image.
TEST_F(GlTest, TiledSplattingKeepsEveryEntryOfCrowdedTilesWithinTheDriversLoopLimit) {
    const TransferFunction faint = fromSharedPoints("faint", {{0.0, {1.0, 0.6, 0.2}, 0.02}, {1.0, {0.2, 0.6, 1.0}, 0.04}});
    const Camera fromAbove{.azimuthDeg = 0, .elevationDeg = 80};
    // Slices of 190 x 190 and 300 x 300 voxels on one 8x8 tile: 36,100 entries a slice (two slices go in
    // parts) and 90,000 (one slice is too many for the loop limit).
    for (int n : {190, 300}) {
        const SplatScene scene = buildSplatScene(makeCheckerboard({n, n, 2}, 30), faint);
        const ImagePlane plane = makeImagePlane(fromAbove, scene.centre, scene.radius, 8, 8);
        ASSERT_EQ(chooseTraversal(plane).axis, 2);
        for (auto mode : {Compositing::SheetBackToFront, Compositing::XRay}) {
            const std::string name = "gl_tiles_crowded_" + std::to_string(n) + "_" + compositingName(mode);
            SCOPED_TRACE(name);
            const Image cpu = renderReference(scene, plane, tiled(mode));
            EXPECT_GT(imageStats(cpu).coveredFraction, 0.3);
            SplatRenderer r;
            r.setScene(scene);
            for (auto primitive : {SplatSettings::Primitive::Tiles, SplatSettings::Primitive::Auto}) {
                SplatSettings s = tiled(mode);
                s.primitive = primitive;
                // llvmpipe's profile refuses in render(); a GPU's, which reads nothing back inside a
                // frame, where the image is first used (the frame drawn again the checked way).
                Image image;
                try {
                    r.render(plane, s);
                    image = r.readback();
                } catch (const RenderError& e) {
                    EXPECT_EQ(primitive, SplatSettings::Primitive::Tiles) << e.what();
                    EXPECT_NE(std::string(e.what()).find("loop iterations"), std::string::npos) << e.what();
                    continue;
                }
                EXPECT_IMAGES_CLOSE(image, cpu, kGlVsCpu, name);
            }
        }
    }
    // Runs of 512 x 512 voxels (a uniform slice is one bucket): the record pass deals them to more
    // workgroups, and every splat is recorded.
    Volume slabs = makeCheckerboard({512, 512, 2}, 1024);   // all 0; the second slice becomes 1
    std::fill(slabs.values.floats().begin() + std::ptrdiff_t(slabs.index(0, 0, 1)), slabs.values.floats().end(), 1.0f);
    updateRange(slabs);
    const SplatScene uniform = buildSplatScene(slabs, faint);
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 0, .elevationDeg = 80}, uniform.centre,
                                            uniform.radius, 64, 64);
    SplatSettings s = tiled(Compositing::XRay);
    s.counters = true;
    SplatRenderer r;
    r.setScene(uniform);
    r.render(plane, s);
    SplatCounters cpuCounters;
    const Image cpu = renderReference(uniform, plane, s, &cpuCounters);
    EXPECT_GT(cpuCounters.drawn, 500000u);
    expectCountersEqual(r.stats().counters, cpuCounters);
    EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, "gl_tiles_long_run");
}

TEST_F(GlTest, TiledSplattingTakesTheGaussianByRecurrenceOnlyWhereFootprintsHoldTheLowPass) {
    // The composite takes the Gaussian down a column by recurrence where every footprint's conic is at
    // most 1 (footprintsHoldThePixel): low-pass and EWA, and reconstruction-only and adaptive where the
    // kernels span a pixel or more. Reconstruction-only footprints this far away have a sigma of 0.06 px
    // (c about 240): started at the tile's first row, the products would under- and overflow, and the
    // pixels whose centre a splat's ellipse holds would take 0 or NaN instead of the Gaussian.
    const auto [scene, plane] = farMarschnerLobb();
    SplatRenderer r;
    r.setScene(scene);
    for (auto filter : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa}) {
        const std::string name = std::string("gl_tiles_far_") + filterModeName(filter);
        SCOPED_TRACE(name);
        SplatSettings s = tiled(Compositing::SheetFrontToBack);
        s.filter = filter;
        s.density = 4.0;
        EXPECT_EQ(footprintsHoldThePixel(filter, scene.dims, scene.origin, scene.spacing, plane, s),
                  filter != FilterMode::Reconstruction);
        r.render(plane, s);
        const Image cpu = renderReference(scene, plane, s);
        EXPECT_GT(imageStats(cpu).coveredFraction, 0.01);
        EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, name);
    }
    // Close up, reconstruction-only kernels of 2 px and more: by recurrence, with the oracle's image,
    // forced and where adaptive mixes reconstruction-only patches with EWA ones (hysteresis on).
    const ImagePlane near = makeImagePlane(Camera{.azimuthDeg = 20, .elevationDeg = 15, .distance = 1.3}, scene.centre,
                                           scene.radius, 96, 84);
    for (auto filter : {FilterMode::Reconstruction, FilterMode::Adaptive})
        for (auto mode : {Compositing::SheetFrontToBack, Compositing::XRay}) {
            const std::string name = std::string("gl_tiles_near_") + filterModeName(filter) + "_" + compositingName(mode);
            SCOPED_TRACE(name);
            SplatSettings s = tiled(mode);
            s.filter = filter;
            s.hysteresis = 0.25;
            s.density = 4.0;
            s.heatmap = true;
            s.counters = true;
            ASSERT_TRUE(footprintsHoldThePixel(filter, scene.dims, scene.origin, scene.spacing, near, s));
            r.render(near, s);
            expectFrameMatchesCpu(r, scene, near, s, name);
            EXPECT_GT(r.stats().counters.drawnPerMode[0], 0u);
            if (filter == FilterMode::Adaptive) {
                EXPECT_GT(r.stats().counters.drawnPerMode[2], 0u);
            }
        }
}

TEST_F(GlTest, TiledSplattingCarriesTheImageAcrossChunksLikeTheCpu) {
    // 72 slices: back to front and X-ray bin them in two chunks (64 at a time), front to back in five
    // (occlusionSlices). The image and heatmap pass from chunk to chunk; X-ray resolves after the last.
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(72), ramp(0.5));
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 20, .elevationDeg = 15}, scene.centre, scene.radius, 64, 56);
    ASSERT_EQ(scene.dims[chooseTraversal(plane).axis], 72);
    SplatRenderer r;
    r.setScene(scene);
    for (auto mode : {Compositing::SheetBackToFront, Compositing::SheetFrontToBack, Compositing::XRay}) {
        SCOPED_TRACE(compositingName(mode));
        SplatSettings s = tiled(mode);
        s.heatmap = true;
        s.counters = true;
        r.render(plane, s);
        expectFrameMatchesCpu(r, scene, plane, s, std::string("gl_tiles_chunks_") + compositingName(mode));
    }
}

TEST_F(GlTest, TiledSplattingLengthensChunksUntilATileIsOpaqueLikeTheCpu) {
    const auto [scene, plane] = wallsAndFill();
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s = tiled(Compositing::SheetFrontToBack);
    s.density = 8.0;
    s.heatmap = true;
    s.counters = true;
    r.render(plane, s);
    expectFrameMatchesCpu(r, scene, plane, s, "gl_tiles_lengthened_chunks");
    EXPECT_GT(r.stats().counters.culledOccluded, 0u);
    // Auto rasterises where one slice's lists do not fit (here: a cap of one texel), with the same chunks.
    r.setTexelBufferLimit(1);
    s.primitive = SplatSettings::Primitive::Auto;
    r.render(plane, s);
    EXPECT_FALSE(r.stats().tiles);
    expectFrameMatchesCpu(r, scene, plane, s, "gl_raster_lengthened_chunks");
}

TEST_F(GlTest, ChunksWhoseListsDoNotFitGoInPartsWithTheCpuOraclesImageAndCounters) {
    // Caps on the lists under what a chunk needs (a GPU with a smaller GL_MAX_TEXTURE_BUFFER_SIZE, or a
    // larger view): auto still tiles while one slice fits, and a chunk goes again in parts. The
    // parts cull against the map their chunk began with: the part after the left wall must not cull
    // the fill behind it, or the counters (and the entries) would differ from the oracle's.
    const auto [scene, plane] = wallsAndFill();
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    s.density = 8.0;
    s.heatmap = true;
    s.counters = true;
    r.render(plane, s);
    ASSERT_TRUE(r.stats().tiles);
    EXPECT_EQ(r.stats().tileListSplits, 0);
    const uint64_t entries = r.stats().tileEntries;
    SplatCounters cpuCounters;
    Image cpuHeat;
    const Image cpu = renderReference(scene, plane, s, &cpuCounters, &cpuHeat);
    int framesSplit = 0;
    for (uint64_t cap = entries; cap > 0; cap /= 3) {   // 2 texels an entry: half the lists, then less
        SCOPED_TRACE("cap " + std::to_string(cap) + " texels");
        r.setTexelBufferLimit(cap);
        r.render(plane, s);
        if (!r.stats().tiles) break;   // a slice did not fit: rasterised (the test below)
        framesSplit += r.stats().tileListSplits > 0;
        EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, "gl_tiles_parts");
        EXPECT_IMAGES_CLOSE(r.readbackHeatmap(), cpuHeat, kGlVsCpu, "gl_tiles_parts_heatmap");
        expectCountersEqual(r.stats().counters, cpuCounters);
        EXPECT_EQ(r.stats().tileEntries, entries);
    }
    EXPECT_GE(framesSplit, 2);
    EXPECT_FALSE(r.stats().tiles) << "a cap of 1 texel must rasterise";
    // Forced tiles refuse a slice that cannot fit, and say so.
    s.primitive = SplatSettings::Primitive::Tiles;
    r.setTexelBufferLimit(1);
    try {
        r.render(plane, s);
        ADD_FAILURE() << "expected a RenderError";
    } catch (const RenderError& e) {
        EXPECT_NE(std::string(e.what()).find("one slice's"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("use points or quads"), std::string::npos) << e.what();
    }
}

TEST_F(GlTest, ListChunksOfAnySizeGiveTheCpuOraclesImage) {
    // Back to front and X-ray bin the slices in chunks only to bound memory (16 on llvmpipe, 64 on a
    // GPU): one slice a chunk, an odd size and all 20 slices at once give the oracle's image.
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(20), ramp());
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 35, .elevationDeg = 25}, scene.centre, scene.radius, 64, 56);
    SplatRenderer r;
    r.setScene(scene);
    for (auto mode : {Compositing::SheetBackToFront, Compositing::XRay}) {
        const SplatSettings s = tiled(mode);
        const Image cpu = renderReference(scene, plane, s);
        EXPECT_GT(imageStats(cpu).coveredFraction, 0.2);
        for (uint32_t slices : {1u, 7u, 64u}) {
            r.setListChunkSlices(slices);
            r.render(plane, s);
            EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu,
                                std::string("gl_tiles_list_chunks_") + compositingName(mode) + "_" + std::to_string(slices));
        }
    }
}

TEST_F(GlTest, TiledFramesHoldRecordsForAChunkNotForTheWholeFrame) {
    // Records are numbered afresh in each chunk: in chunks of 4 of 40 slices, the frame's working buffers
    // (records, lists, bins) take far less than records for every splat would (48 bytes each), and the
    // image is the oracle's. Sized for the frame, the records alone took 1.25 times that.
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(40), ramp());
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 35, .elevationDeg = 25}, scene.centre, scene.radius, 64, 56);
    SplatRenderer r;
    r.setScene(scene);
    r.setListChunkSlices(4);
    const SplatSettings s = tiled(Compositing::XRay);
    r.render(plane, s);
    const uint64_t allRecords = r.stats().splatsDrawn * 48;
    ASSERT_GT(allRecords, 1000000u);
    EXPECT_LT(r.workingBytes(), allRecords / 2);
    EXPECT_IMAGES_CLOSE(r.readback(), renderReference(scene, plane, s), kGlVsCpu, "gl_tiles_chunk_records");
}

TEST_F(GlTest, ChunksWhoseRecordsDoNotFitGoInPartsToo) {
    // The scatter reads the records through a texel buffer too, 3 texels a splat against 2 an entry.
    // Footprints of 0.06 px (reconstruction only, far away) touch one tile each, so the records need more
    // texels than the lists: a cap between the two must split the chunk, or the scatter would read
    // records past the end of what the driver lets it see.
    const auto [scene, plane] = farMarschnerLobb();
    SplatRenderer r;
    r.setScene(scene);
    r.setListChunkSlices(64);   // the 40 slices in one chunk, so the frame's counts are the chunk's
    SplatSettings s = tiled(Compositing::XRay);
    s.filter = FilterMode::Reconstruction;
    s.counters = true;
    r.render(plane, s);
    const uint64_t splats = r.stats().counters.drawn, entries = r.stats().tileEntries;
    ASSERT_GT(3 * splats, 2 * entries + 16) << "the records must take more texels than the lists";
    r.setTexelBufferLimit(entries + splats + splats / 2);   // between 2 texels an entry and 3 a splat
    r.render(plane, s);
    EXPECT_GT(r.stats().tileListSplits, 0);
    EXPECT_EQ(r.stats().tileEntries, entries);
    const Image cpu = renderReference(scene, plane, s);
    EXPECT_GT(imageStats(cpu).coveredFraction, 0.01);
    EXPECT_IMAGES_CLOSE(r.readback(), cpu, kGlVsCpu, "gl_tiles_record_parts");
}

TEST_F(GlTest, AutoTilesSheetsAndXRayRastersTheRestAndFallsBackWhereASlicesListsDoNotFit) {
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(16), ramp());
    SplatRenderer r;
    r.setScene(scene);
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, 64, 56);
    for (auto mode : {Compositing::SplatEverySample, Compositing::SheetBackToFront, Compositing::SheetFrontToBack,
                      Compositing::XRay}) {
        SplatSettings s;
        s.compositing = mode;
        r.render(plane, s);
        EXPECT_EQ(r.stats().tiles, mode != Compositing::SplatEverySample) << compositingName(mode);
        EXPECT_EQ(r.stats().tiles, tiledSplatting(s));
    }
    // The camera inside the volume (footprints have no bound there): tiles, the oracle's image and
    // counters. Where one slice's lists cannot fit (here: a cap of one texel) auto draws the frame again
    // rasterised, with tiles' semantics (refresh every slice, the opaque-tile map culled against taken
    // once a chunk of occlusionSlices): the same image and counters.
    const SplatScene deep = buildSplatScene(makeMarschnerLobb(40), ramp());
    r.setScene(deep);
    const ImagePlane inside = makeImagePlane(Camera{.distance = 0.3, .fovYDeg = 60}, deep.centre, deep.radius, 64, 56);
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    s.density = 8.0;
    s.counters = true;
    SplatCounters cpu;
    const Image reference = renderReference(deep, inside, s, &cpu);
    r.render(inside, s);
    EXPECT_TRUE(r.stats().tiles);
    EXPECT_IMAGES_CLOSE(r.readback(), reference, kGlVsCpu, "gl_auto_inside");
    expectCountersEqual(r.stats().counters, cpu);
    r.setTexelBufferLimit(1);
    r.render(inside, s);
    EXPECT_FALSE(r.stats().tiles);
    EXPECT_IMAGES_CLOSE(r.readback(), reference, kGlVsCpu, "gl_auto_fallback");
    expectCountersEqual(r.stats().counters, cpu);
    EXPECT_GT(cpu.culledNear, 0u) << "the camera must be inside the volume";
    EXPECT_GT(cpu.culledOccluded, 0u) << "the second chunk must be culled against the first";
}

TEST_F(GlTest, TiledSplattingRefusesSplatEverySampleAndRendersAfterwards) {
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(12), ramp());
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, 48, 40);
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s = tiled(Compositing::SplatEverySample);
    try {
        r.render(plane, s);
        FAIL() << "splat-every-sample with tiles must be refused";
    } catch (const RenderError& e) {
        EXPECT_NE(std::string(e.what()).find("splat-every-sample needs points or quads"), std::string::npos) << e.what();
    }
    s.compositing = Compositing::XRay;
    r.render(plane, s);
    EXPECT_IMAGES_CLOSE(r.readback(), renderReference(scene, plane, s), kGlVsCpu, "gl_tiles_after_refusal");
}

TEST_F(GlTest, TheCompositeOfAPixelAnInvocationMatchesTheCpuInEveryMode) {
    // The composite's other layout (tile_composite_pixels.comp: a pixel per invocation, each batch of 64
    // entries staged in shared memory), which no driver takes by default until a GPU has measured it:
    // every sheet and X-ray mode with its heatmap and counters (front to back with early termination and
    // culling), shading both ways, and a tile crowded past hundreds of batches a slice.
    Volume v = makeMarschnerLobb(20);
    v.spacing = {1.0, 1.5, 1.0};
    SplatScene scene = buildSplatScene(v, ramp());
    addGradients(scene, *computeGradients(v));
    const ImagePlane plane = makeImagePlane(Camera{.azimuthDeg = 35, .elevationDeg = 25, .distance = 1.4},
                                            scene.centre, scene.radius, 100, 84);
    SplatRenderer r;
    r.setCompositePerPixel(true);
    r.setScene(scene);
    for (auto mode : {Compositing::SheetBackToFront, Compositing::SheetFrontToBack, Compositing::XRay}) {
        const std::string name = std::string("gl_pixels_") + compositingName(mode);
        SCOPED_TRACE(name);
        SplatSettings s = tiled(mode);
        s.density = 4.0;
        s.heatmap = true;
        s.counters = true;
        r.render(plane, s);
        expectFrameMatchesCpu(r, scene, plane, s, name);
    }
    for (auto shading : {SplatSettings::Shading::PerSplat, SplatSettings::Shading::PerFragment}) {
        SCOPED_TRACE(int(shading));
        SplatSettings s = tiled(Compositing::SheetFrontToBack);
        s.shading = shading;
        r.render(plane, s);
        EXPECT_IMAGES_CLOSE(r.readback(), renderReference(scene, plane, s), kGlVsCpu, "gl_pixels_shaded");
    }
    // 36,100 entries a slice on one 8x8 tile: 565 batches, and two slices go in parts for the loop limit.
    const TransferFunction faint = fromSharedPoints("faint", {{0.0, {1.0, 0.6, 0.2}, 0.02}, {1.0, {0.2, 0.6, 1.0}, 0.04}});
    const SplatScene crowded = buildSplatScene(makeCheckerboard({190, 190, 2}, 30), faint);
    const ImagePlane tile = makeImagePlane(Camera{.azimuthDeg = 0, .elevationDeg = 80}, crowded.centre, crowded.radius, 8, 8);
    r.setScene(crowded);
    for (auto mode : {Compositing::SheetBackToFront, Compositing::XRay}) {
        r.render(tile, tiled(mode));
        EXPECT_IMAGES_CLOSE(r.readback(), renderReference(crowded, tile, tiled(mode)), kGlVsCpu, "gl_pixels_crowded");
    }
}
