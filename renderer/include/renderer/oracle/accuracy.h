// The measurements behind docs/accuracy.md that tests also assert: error per image region, where the
// regions are the adaptive classifier's verdict on each pixel's ray, and the scene of 000 fig. 8 (a
// grazing checkerboard, magnified near the eye and minified towards the horizon). Writing the report
// is the CLI's job (app/accuracy.cpp); nothing here renders.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/io/image.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/volume.h"

#include <cstdint>
#include <string>
#include <vector>

namespace renderer {

// A named scene with its view, as the hard cases have (hard_cases.h).
struct ViewedVolume {
    std::string name;
    Volume volume;
    TransferFunction tf;
    Camera camera;
    int width = 0, height = 0;
};

// 000 fig. 8: a board x board x 3 checkerboard of `cell`-voxel cells, every voxel opaque (black and
// white), seen from just above the near edge along +x (40 degree fov). At height = board / 8 (512
// board at 64 rows) the bottom quarter of the rows is magnified and the top few rows minified at the
// paper's c_min and c_max. A taller image cannot show both: c_max / c_min ~ 8 is the depth ratio the
// board must span, and minified depths (0.7 f_px c_max voxels) grow with the image height.
ViewedVolume grazingCheckerboard(int board, int cell, int width, int height);

// The window (x0, y0, width, height) of `plane` as an image plane of its own: the same camera with the
// principal point moved, so splatting and the ground truth of a crop equal those pixels of the whole.
ImagePlane cropPlane(const ImagePlane& plane, int x0, int y0, int width, int height);

// What the classifier (classifier.h) says about a pixel: Magnified when its centre ray enters and
// leaves the box of voxel centres at depths that both take reconstruction only, Minified when both
// take low-pass only, Transition otherwise, Empty when the ray misses the box. Conservative like the
// patch rule (000 sec. 4.1): a shortcut region only where the whole stretch of ray agrees.
enum class Region : uint8_t { Empty, Magnified, Transition, Minified };
const char* regionName(Region r); // "empty", "magnified", "transition", "minified"
std::vector<Region> classifyPixels(const SplatScene& scene, const ImagePlane& plane,
                                   const SplatSettings& settings);

struct RegionError {
    size_t pixels = 0;
    double rmse = 0.0;      // premultiplied RGBA over the region's pixels, as metrics.h
    double psnrDb = 0.0;    // 20 log10(1 / rmse); +inf when identical
    double alphaBias = 0.0; // mean alpha of the image minus that of the reference: > 0 over-covers
};
// Error of `image` against `reference` over the pixels whose region is `region`. Throws RenderError
// when the sizes differ.
RegionError regionError(const Image& image, const Image& reference, const std::vector<Region>& regions,
                        Region region);

} // namespace renderer
