// Post-classified shading (post_classification.h): the ground truth lights a ball as a ray-traced
// sphere lit with its analytic normal would be lit, and the image-aligned slabs follow that truth.
#include "renderer/errors.h"
#include "renderer/math/metrics.h"
#include "renderer/math/shading.h"
#include "renderer/model/gradients.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/hard_cases.h"
#include "renderer/oracle/image_slabs.h"
#include "test_paths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace renderer;

namespace {

constexpr int kSize = 40;          // voxels a side
constexpr double kRadius = 14.0;   // voxels: the surface the TF shows
const glm::dvec3 kOrange(1.0, 0.6, 0.2);

// A ball whose value falls linearly with the distance from the grid's centre, zero at kRadius, under a
// TF opaque orange from that value up: the post-classified surface is the sphere of radius kRadius.
SplatScene ballScene(Volume& v) {
    v.name = "ball";
    v.dims = {kSize, kSize, kSize};
    v.values.floats().resize(v.voxelCount());
    const double c = (kSize - 1) / 2.0;
    for (int z = 0; z < kSize; ++z)
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x)
                v.values.floats()[v.index(x, y, z)] = float(kRadius - glm::length(glm::dvec3(x, y, z) - c));
    updateRange(v);
    const double at = (0.0 - v.range.lo) / (v.range.hi - v.range.lo);   // the window fraction of value 0
    const TransferFunction tf =
        fromSharedPoints("ball", {{0.0, kOrange, 0.0}, {at - 0.002, kOrange, 0.0}, {at + 0.002, kOrange, 1.0}, {1.0, kOrange, 1.0}});
    SplatScene scene = buildSplatScene(v, tf);
    addGradients(scene, *computeGradients(v));
    return scene;
}

// Opaque within a small fraction of a voxel of the surface, lit per fragment.
SplatSettings litOpaque() {
    SplatSettings s;
    s.density = 50.0;
    s.shading = SplatSettings::Shading::PerFragment;
    return s;
}

ImagePlane ballView(const SplatScene& ball, bool orthographic = false) {
    Camera camera{35, 25, 2.5, 30.0};
    camera.orthographic = orthographic;
    return makeImagePlane(camera, ball.centre, ball.radius, 48, 48);
}

} // namespace

// One ray per pixel through the truth against a ray-traced sphere of radius kRadius, lit by shading.h's
// Phong with the sphere's analytic normal (specular included), on every pixel whose ray passes at least
// two voxels inside the silhouette (beyond, the ray grazes the surface and partial coverage decides).
TEST(PostShading, TheTruthLightsABallAsItsAnalyticNormal) {
    Volume v;
    const SplatScene scene = ballScene(v);
    const SplatSettings s = litOpaque();
    for (const bool orthographic : {false, true}) {
        const ImagePlane plane = ballView(scene, orthographic);
        const Image truth = renderGroundTruth(scene, plane, s, GroundTruthOptions{.tolerance = 1e-4, .supersample = 0, .postClassified = true});
        const glm::dmat3 objectFromView = glm::transpose(plane.viewFromObject);
        const glm::dvec3 centre = scene.origin + scene.spacing * ((kSize - 1) / 2.0);
        const double radius = kRadius * scene.spacing.x;
        double worst = 0.0, sum = 0.0;
        int pixels = 0;
        for (int y = 0; y < plane.height; ++y)
            for (int x = 0; x < plane.width; ++x) {
                const glm::dvec2 m = (glm::dvec2(x + 0.5, y + 0.5) - plane.centrePx) / plane.fPx;
                const glm::dvec3 dirCamera = orthographic ? glm::dvec3(0, 0, 1) : glm::normalize(glm::dvec3(m, 1.0));
                const glm::dvec3 origin = objectFromView * ((orthographic ? glm::dvec3(m, 0.0) : glm::dvec3(0.0)) - plane.translation);
                const glm::dvec3 dir = objectFromView * dirCamera;
                const double along = glm::dot(centre - origin, dir);
                const double miss = glm::length(origin + along * dir - centre);
                if (miss > radius - 2.0 * scene.spacing.x) continue;
                const glm::dvec3 hit = origin + (along - std::sqrt(radius * radius - miss * miss)) * dir;
                const glm::dvec3 expected = shade(kOrange, plane.viewFromObject * glm::normalize(hit - centre), -dirCamera, s.shadingParams);
                const float* p = truth.pixel(x, y);
                EXPECT_GT(p[3], 0.999f) << x << "," << y;
                for (int c = 0; c < 3; ++c) {
                    const double e = std::abs(p[c] - expected[c]);
                    worst = std::max(worst, e);
                    sum += e;
                }
                ++pixels;
            }
        std::printf("[ post shading ] ball, %s: %d pixels, colour off the analytic normal's by %.4f at most, %.4f on "
                    "average\n", orthographic ? "orthographic" : "perspective", pixels, worst, sum / (3.0 * pixels));
        EXPECT_GT(pixels, 400);
        EXPECT_LT(worst, 0.05);
        EXPECT_LT(sum / (3.0 * pixels), 0.01);
    }
}

// Shaded, the post-classified slabs follow their own truth as unshaded ones do. On the ball against one
// ray per pixel: its silhouette is a sharp TF's, finer than a pixel, which the slabs do not filter
// (measured against the filtered truth 25.4 dB at every thickness and filter; against one ray 51.2 / 56.1
// / 59.4 dB at 0.5 / 0.25 / 0.125 voxels). Marschner-Lobb, magnified, against the filtered truth.
TEST(PostShading, SlabsFollowTheShadedTruth) {
    Volume v;
    const SplatScene ball = ballScene(v);
    const SplatSettings s = litOpaque();
    const GroundTruthOptions o{.tolerance = 1e-4, .supersample = 2, .postClassified = true};
    const auto cache = testing_support::testOutputDir() / "gt_cache";
    const ImagePlane plane = ballView(ball);
    GroundTruthOptions oneRay = o;
    oneRay.supersample = 0;
    const Image ballTruth = cachedGroundTruth(ball, plane, s, oneRay, cache);
    const double onBall = compareImages(renderImageAlignedSlabs(ball, plane, s, SlabOptions{0.25, true}), ballTruth).psnrDb;

    HardCase hc = hardCases(1, "marschner-lobb").at(0);
    SplatScene ml = buildSplatScene(hc.volume, hc.tf);
    addGradients(ml, *computeGradients(hc.volume));
    hc.settings.shading = SplatSettings::Shading::PerFragment;
    const ImagePlane mlPlane = makeImagePlane(hc.camera, ml.centre, ml.radius, hc.width, hc.height);
    const Image mlTruth = cachedGroundTruth(ml, mlPlane, hc.settings, o, cache);
    const double onMl = compareImages(renderImageAlignedSlabs(ml, mlPlane, hc.settings, SlabOptions{0.5, true}), mlTruth).psnrDb;
    hc.settings.shading = SplatSettings::Shading::None;
    const double shadingMatters = compareImages(cachedGroundTruth(ml, mlPlane, hc.settings, o, cache), mlTruth).psnrDb;
    std::printf("[ post shading ] slabs against the shaded post-classified truth: ball (0.25 voxels, one ray a pixel) "
                "%.2f dB, marschner-lobb (0.5) %.2f dB; the unshaded truth is %.2f dB from the shaded\n", onBall, onMl,
                shadingMatters);
    EXPECT_GT(onBall, 50.0);
    EXPECT_GT(onMl, 42.0);
    EXPECT_GT(onMl, shadingMatters + 20.0) << "the slabs must be lit, not just classified";
}

// The ball's silhouette is finer than a pixel: one sample a pixel aliases it against the filtered truth,
// and S x S samples resolved by the truth's own filter (SlabOptions::supersample) close the gap, as
// reconstruction-only slabs then leave the pixel filter to the resolve alone.
TEST(PostShading, SupersampledSlabsResolveTheSilhouette) {
    Volume v;
    const SplatScene ball = ballScene(v);
    SplatSettings s = litOpaque();
    s.filter = FilterMode::Reconstruction;
    const ImagePlane plane = ballView(ball);
    const Image truth = cachedGroundTruth(ball, plane, s, {.tolerance = 1e-4, .supersample = 2, .postClassified = true},
                                          testing_support::testOutputDir() / "gt_cache");
    double psnr[3];
    for (int ss = 0; ss <= 2; ++ss)
        psnr[ss] = compareImages(renderImageAlignedSlabs(ball, plane, s, SlabOptions{0.25, true, ss}), truth).psnrDb;
    std::printf("[ post shading ] ball against the filtered truth: slabs with 1 / 1x1 / 2x2 samples a pixel %.2f / "
                "%.2f / %.2f dB\n", psnr[0], psnr[1], psnr[2]);
    EXPECT_LT(psnr[0], 30.0) << "one unresolved sample a pixel aliases the silhouette";
    EXPECT_GT(psnr[2], 40.0);
    EXPECT_GT(psnr[2], psnr[0] + 10.0);
    EXPECT_THROW(renderImageAlignedSlabs(ball, plane, s, SlabOptions{0.25, true, kMaxSlabSupersample + 1}), RenderError);
    EXPECT_THROW(renderImageAlignedSlabs(ball, plane, s, SlabOptions{0.25, true, -1}), RenderError);
}

// Shading needs the scene's gradients, post-classified as pre-classified: refused by name without them.
TEST(PostShading, RefusesAShadedSceneWithoutGradients) {
    const HardCase hc = hardCases(1, "marschner-lobb").at(0);
    const SplatScene scene = buildSplatScene(hc.volume, hc.tf);
    const ImagePlane plane = makeImagePlane(hc.camera, scene.centre, scene.radius, 16, 16);
    SplatSettings s;
    s.shading = SplatSettings::Shading::PerFragment;
    EXPECT_THROW(renderImageAlignedSlabs(scene, plane, s, SlabOptions{0.5, true}), RenderError);
    EXPECT_THROW(renderGroundTruth(scene, plane, s, GroundTruthOptions{.postClassified = true}), RenderError);
}
