// The near layer on the GL path (near_layer_pass.cpp): in the near-eye views it agrees with the CPU
// oracle (tolerance: gl_fixture.h) in tiles, the rasteriser and X-ray, with the same counts, and so stays
// as close to the ground truth as the oracle (tests/unit/test_near_layer.cpp).
#include "gl_fixture.h"
#include "image_compare.h"
#include "test_paths.h"

#include "renderer/gl/splat_renderer.h"
#include "renderer/math/metrics.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/hard_cases.h"
#include "renderer/oracle/reference_renderer.h"

#include <cstdio>

using namespace renderer;

TEST_F(GlTest, NearLayerMatchesCpuAndTheGroundTruthInEveryPath) {
    struct Path {
        const char* name;
        Compositing compositing;
        SplatSettings::Primitive primitive;
    };
    const Path paths[] = {{"tiles", Compositing::SheetFrontToBack, SplatSettings::Primitive::Tiles},
                          {"raster", Compositing::SplatEverySample, SplatSettings::Primitive::Raster},
                          {"raster-sheets", Compositing::SheetBackToFront, SplatSettings::Primitive::Raster},
                          {"xray-tiles", Compositing::XRay, SplatSettings::Primitive::Tiles}};
    GroundTruthOptions o;
    o.supersample = 2;
    o.tolerance = 1e-4;
    for (const HardCase& hc : nearEyeCases()) {
        const SplatScene scene = buildSplatScene(hc.volume, hc.tf);
        const ImagePlane plane = makeImagePlane(hc.camera, scene.centre, scene.radius, hc.width, hc.height);
        SplatRenderer r;
        r.setScene(scene);
        for (const Path& p : paths)
            for (FilterMode mode : {FilterMode::Ewa, FilterMode::Adaptive}) {
                SplatSettings s = hc.settings;
                s.compositing = p.compositing;
                s.primitive = p.primitive;
                s.filter = mode;
                s.counters = true;
                r.render(plane, s);
                const Image gl = r.readback();
                SplatCounters cpuCounters;
                const Image cpu = renderReference(scene, plane, s, &cpuCounters);
                const std::string name = hc.name + "_" + p.name + "_" + filterModeName(mode);
                EXPECT_IMAGES_CLOSE(gl, cpu, kGlVsCpu, "near_layer_" + name);
                expectCountersEqual(r.stats().counters, cpuCounters);
                EXPECT_GT(r.stats().counters.nearLayer, 0u) << name;
                const Image gt =
                    cachedGroundTruth(scene, plane, s, o, testing_support::testOutputDir() / "gt_cache");
                const double psnr = compareImages(gl, gt).psnrDb;
                std::printf("[ near-eye gl ] %-32s PSNR %6.2f dB\n", name.c_str(), psnr);
                EXPECT_GT(psnr, 36.5) << name; // the oracle's floor (test_near_layer.cpp)
            }
    }
}
