// Error of an image against a reference, as EWA_NOTES defines it: RMSE of premultiplied RGBA in [0,1]
// over all four channels, PSNR from it (peak 1), SSIM on luminance as a second figure, max error; and
// the one quantile rule the measurements report with.
#pragma once
#include "renderer/io/image.h"

#include <vector>

namespace renderer {

struct ImageError {
    double rmse = 0.0;
    double psnrDb = 0.0;      // 20 log10(1 / rmse); +inf for identical images
    double ssim = 1.0;        // mean SSIM of luminance, 11x11 Gaussian window (sigma 1.5)
    double maxAbs = 0.0;      // largest |a - b| over all channels
    int maxX = -1, maxY = -1; // where it is
};

// Throws RenderError when the sizes differ.
ImageError compareImages(const Image& image, const Image& reference);
// |a - b| per channel times `gain`, opaque, for looking at where two images differ.
Image differenceImage(const Image& a, const Image& b, double gain);

// The q-quantile (0..1) of `values` by nearest rank: the ceil(q n)-th smallest (the first for q = 0), so
// the median of an even count is the lower middle value; 0 when there are none.
double nearestRankQuantile(std::vector<double> values, double q);

} // namespace renderer
