// The claims of 000 sec. 3.2 and fig. 8, measured against the ground truth per image region on the
// grazing 512x512x3 checkerboard (accuracy.h): reconstruction-only errs more than EWA where the board
// is minified, low-pass-only errs more where it is magnified, and adaptive EWA at the paper's c_min and
// c_max stays within a small margin of full EWA. docs/accuracy.md shows the whole image; the test keeps
// to two 32-column crops (the magnified bottom rows, the minified top rows) so its reference takes a
// few seconds (the left 32 columns; the whole image is in the report).
#include "renderer/oracle/accuracy.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/reference_renderer.h"
#include "test_paths.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace renderer;

namespace {

// The pixels (x0.., y0..) of a whole-image render: splatting is per pixel, so this is the crop's render.
Image cropImage(const Image& image, int x0, int y0, int w, int h) {
    Image out(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c)
                out.pixel(x, y)[c] = image.pixel(x0 + x, y0 + y)[c];
    return out;
}

std::vector<Region> cropRegions(const std::vector<Region>& regions, int width, int x0, int y0, int w, int h) {
    std::vector<Region> out;
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x)
            out.push_back(regions[size_t(y) * size_t(width) + size_t(x)]);
    return out;
}

} // namespace

TEST(PaperClaims, EachFilterShortcutLosesOnlyWhereThePaperSaysAndAdaptiveStaysCloseToEwa) {
    const ViewedVolume board = grazingCheckerboard(512, 8, 128, 64);
    const SplatScene scene = buildSplatScene(board.volume, board.tf);
    const ImagePlane plane =
        makeImagePlane(board.camera, scene.centre, scene.radius, board.width, board.height);
    const std::vector<Region> regions = classifyPixels(scene, plane, SplatSettings{});

    struct Crop {
        Region region;
        int y0, rows;
    };
    // The top 2 rows are minified, the bottom 8 magnified (the classifier's verdict, checked below; c_max
    // from the 128x64 image's corner).
    const int x0 = 0, cols = 32;
    const Crop crops[] = {{Region::Minified, 0, 2}, {Region::Magnified, 56, 8}};
    const FilterMode modes[] = {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa,
                                FilterMode::Adaptive};
    Image images[4];
    for (int m = 0; m < 4; ++m) {
        SplatSettings s;
        s.filter = modes[m];
        images[m] = renderReference(scene, plane, s);
    }
    GroundTruthOptions o;
    o.supersample = 2;
    o.tolerance = 1e-4;
    for (const Crop& c : crops) {
        const std::vector<Region> labels = cropRegions(regions, plane.width, x0, c.y0, cols, c.rows);
        const size_t inRegion = size_t(std::count(labels.begin(), labels.end(), c.region));
        ASSERT_GE(inRegion, labels.size() * 9 / 10)
            << regionName(c.region) << ": the crop is not that region";
        const Image gt = cachedGroundTruth(scene, cropPlane(plane, x0, c.y0, cols, c.rows), SplatSettings{},
                                           o, testing_support::testOutputDir() / "gt_cache");
        RegionError e[4];
        for (int m = 0; m < 4; ++m) {
            e[m] = regionError(cropImage(images[m], x0, c.y0, cols, c.rows), gt, labels, c.region);
            std::printf("[ claims ] %-10s %-15s RMSE %.5f  PSNR %6.2f dB  alpha bias %+.4f  (%zu px)\n",
                        regionName(c.region), filterModeName(modes[m]), e[m].rmse, e[m].psnrDb,
                        e[m].alphaBias, e[m].pixels);
        }
        const RegionError &rec = e[0], &low = e[1], &ewa = e[2], &adaptive = e[3];
        if (c.region == Region::Minified) {
            // Reconstruction-only point-samples a checker finer than the pixels (moire); EWA band-limits
            // it. Measured RMSE: reconstruction 0.115, EWA 0.086 (x1.34); both share the far edge's
            // silhouette error (alpha +0.077), which keeps the ratio modest. Bound x1.15.
            EXPECT_GT(rec.rmse, 1.15 * ewa.rmse);
        } else {
            // Low-pass-only shrinks magnified voxels to 1-px dots. Measured RMSE: low-pass 0.255, EWA
            // 0.021 (x12). Bound x3.
            EXPECT_GT(low.rmse, 3.0 * ewa.rmse);
        }
        // Adaptive uses the shortcut only where the classifier allows it; measured within 0.2 dB of EWA
        // (2 %); the bound allows 5 %.
        EXPECT_LT(adaptive.rmse, 1.05 * ewa.rmse) << regionName(c.region);
    }
}
