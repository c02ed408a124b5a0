// Post-classified slabs skip kernels whose whole neighbourhood the TF leaves transparent (post_reach.h):
// the image is exactly the one without the culling, in close, wide-angle, orthographic and minified views,
// and on bonsai a quarter of the kernels go.
#include "renderer/io/volume_io.h"
#include "renderer/model/procedural.h"
#include "renderer/model/transfer_function.h"
#include "renderer/oracle/image_slabs.h"
#include "renderer/oracle/post_reach.h"
#include "test_paths.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

using namespace renderer;

namespace {

// The largest difference of any channel between the culled and the unculled frame; the kernels skipped.
std::pair<double, uint64_t> culledAgainstAll(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& s,
                                             double thickness) {
    SlabCounters culled;
    const Image a = renderImageAlignedSlabs(scene, plane, s, SlabOptions{.thickness = thickness, .postClassified = true}, &culled);
    const Image b = renderImageAlignedSlabs(
        scene, plane, s, SlabOptions{.thickness = thickness, .postClassified = true, .cullTransparent = false});
    double worst = 0.0;
    for (size_t i = 0; i < a.rgba.size(); ++i) worst = std::max(worst, double(std::abs(a.rgba[i] - b.rgba[i])));
    return {worst, culled.skippedTransparent};
}

// Sparse dots in noise, 40^3: values in [0, 0.5) everywhere but 6 dots of 1, which alone the TF shows.
// A dot's neighbours pull its slabs' means down, so a kernel skipped too close to a dot changes the image;
// far from every dot the noise is transparent through and through.
SplatScene dotsScene() {
    Volume v;
    v.name = "dots";
    v.dims = {40, 40, 40};
    v.values.floats().resize(v.voxelCount());
    uint32_t state = 12345u;
    const auto next = [&] { return (state = state * 1664525u + 1013904223u) >> 8; };
    for (float& value : v.values.floats()) value = 0.5f * float(next() % 1000u) / 1000.0f;
    for (int dot = 0; dot < 6; ++dot)
        v.values.floats()[v.index(4 + int(next() % 32u), 4 + int(next() % 32u), 4 + int(next() % 32u))] = 1.0f;
    updateRange(v);
    const glm::dvec3 orange(1.0, 0.6, 0.2);
    return buildSplatScene(v, fromSharedPoints("dots", {{0.0, orange, 0.0}, {0.8, orange, 0.0}, {0.9, orange, 1.0}, {1.0, orange, 1.0}}));
}

} // namespace

TEST(PostReach, CullingTransparentNeighbourhoodsLeavesTheImageExactly) {
    const SplatScene scene = dotsScene();
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    struct View {
        const char* name;
        Camera camera;
        FilterMode filter;
        int size;
        bool skips;   // a minified view's pixels reach across the grid: nothing to skip, only to keep exact
    };
    for (const View& view : {View{"close, EWA", Camera{30, 20, 1.6, 30}, FilterMode::Ewa, 48, true},
                             View{"wide angle, low-pass", Camera{200, -40, 1.5, 70}, FilterMode::LowPass, 128, true},
                             View{"orthographic, adaptive", Camera{.azimuthDeg = 70, .orthographic = true},
                                  FilterMode::Adaptive, 48, true},
                             View{"minified, EWA", Camera{10, 10, 12, 30}, FilterMode::Ewa, 48, false}}) {
        s.filter = view.filter;
        const ImagePlane plane = makeImagePlane(view.camera, scene.centre, scene.radius, view.size, view.size);
        const auto [worst, skipped] = culledAgainstAll(scene, plane, s, 0.5);
        std::printf("[ reach ] dots, %s: %llu of %zu kernels skipped, largest difference %.3g\n", view.name,
                    (unsigned long long)skipped, scene.classes.size(), worst);
        EXPECT_EQ(worst, 0.0) << view.name;
        if (view.skips) {
            EXPECT_GT(skipped, 0u) << view.name << ": noise far from every dot";
        }
    }
}

// On real scans at an editor's view size (512x512), without rendering: how many kernels go, and never
// one whose own class is visible.
TEST(PostReach, OnScansMostOfTheAirGoesAndNoVisibleKernel) {
    for (const auto& [file, tf, least] : {std::tuple{"bonsai.nhdr", "bonsai", 0.2}, std::tuple{"headsq.nhdr", "ct-bone", 0.02}}) {
        const SplatScene scene = buildSplatScene(loadVolume(testing_support::assetDir() / "volumes" / file), builtinPreset(tf));
        SplatSettings s;
        const ImagePlane plane = makeImagePlane(Camera{60, 15, 2.5, 30}, scene.centre, scene.radius, 512, 512);
        const double slab = 0.5 * (scene.spacing.x + scene.spacing.y + scene.spacing.z) / 3.0;
        const std::vector<uint8_t> near = kernelsNearVisible(scene, postReach(scene, plane, s, slab));
        size_t kept = 0, visibleSkipped = 0;
        for (size_t v = 0; v < near.size(); ++v) {
            kept += near[v];
            visibleSkipped += !near[v] && scene.lut[scene.classes[v]].a > 0.0f;
        }
        const double skipped = 1.0 - double(kept) / double(near.size());
        std::printf("[ reach ] %s under %s at 512x512: %.1f %% of %zu kernels skipped\n", file, tf, 100.0 * skipped,
                    near.size());
        EXPECT_EQ(visibleSkipped, 0u) << file;
        EXPECT_GT(skipped, least) << file;
    }
}
