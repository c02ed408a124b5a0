// Image error metrics (see metrics.h). SSIM follows Wang et al. 2004 with their constants
// (K1 = 0.01, K2 = 0.03, dynamic range 1) and an 11x11 Gaussian window of sigma 1.5.
#include "renderer/math/metrics.h"

#include "renderer/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace renderer {

namespace {

std::vector<double> luminance(const Image& img) {
    std::vector<double> y(size_t(img.width) * size_t(img.height));
    for (size_t i = 0; i < y.size(); ++i) {
        const float* p = &img.rgba[i * 4];
        y[i] = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
    return y;
}

// Separable Gaussian blur with clamped borders.
std::vector<double> blur(const std::vector<double>& in, int w, int h) {
    constexpr int kRadius = 5;
    double k[2 * kRadius + 1], sum = 0.0;
    for (int i = -kRadius; i <= kRadius; ++i) sum += k[i + kRadius] = std::exp(-0.5 * i * i / (1.5 * 1.5));
    for (double& v : k) v /= sum;
    std::vector<double> tmp(in.size()), out(in.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double s = 0.0;
            for (int i = -kRadius; i <= kRadius; ++i) s += k[i + kRadius] * in[size_t(y) * w + std::clamp(x + i, 0, w - 1)];
            tmp[size_t(y) * w + x] = s;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double s = 0.0;
            for (int i = -kRadius; i <= kRadius; ++i) s += k[i + kRadius] * tmp[size_t(std::clamp(y + i, 0, h - 1)) * w + x];
            out[size_t(y) * w + x] = s;
        }
    return out;
}

double ssimLuminance(const Image& a, const Image& b) {
    const int w = a.width, h = a.height;
    const std::vector<double> x = luminance(a), y = luminance(b);
    std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
    for (size_t i = 0; i < x.size(); ++i) xx[i] = x[i] * x[i], yy[i] = y[i] * y[i], xy[i] = x[i] * y[i];
    const auto mx = blur(x, w, h), my = blur(y, w, h), sxx = blur(xx, w, h), syy = blur(yy, w, h),
               sxy = blur(xy, w, h);
    constexpr double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    double sum = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
        const double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i], cxy = sxy[i] - mx[i] * my[i];
        sum += ((2 * mx[i] * my[i] + c1) * (2 * cxy + c2)) / ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
    }
    return x.empty() ? 1.0 : sum / double(x.size());
}

} // namespace

ImageError compareImages(const Image& image, const Image& reference) {
    if (image.width != reference.width || image.height != reference.height)
        throw RenderError("cannot compare a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                          " image with a " + std::to_string(reference.width) + "x" +
                          std::to_string(reference.height) + " reference");
    ImageError e;
    double sum = 0.0;
    for (size_t i = 0; i < image.rgba.size(); ++i) {
        const double d = std::abs(double(image.rgba[i]) - double(reference.rgba[i]));
        const double dd = std::isfinite(d) ? d : std::numeric_limits<double>::infinity();
        sum += dd * dd;
        if (!(dd <= e.maxAbs)) {
            e.maxAbs = dd;
            e.maxX = int((i / 4) % size_t(image.width));
            e.maxY = int((i / 4) / size_t(image.width));
        }
    }
    e.rmse = image.rgba.empty() ? 0.0 : std::sqrt(sum / double(image.rgba.size()));
    e.psnrDb = e.rmse > 0.0 ? -20.0 * std::log10(e.rmse) : std::numeric_limits<double>::infinity();
    e.ssim = ssimLuminance(image, reference);
    return e;
}

Image differenceImage(const Image& a, const Image& b, double gain) {
    Image d(a.width, a.height);
    for (size_t i = 0; i < d.rgba.size(); ++i)
        d.rgba[i] = (i % 4 == 3) ? 1.0f : float(std::min(1.0, gain * std::abs(double(a.rgba[i]) - double(b.rgba[i]))));
    return d;
}

double nearestRankQuantile(std::vector<double> values, double q) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t rank = size_t(std::ceil(std::clamp(q, 0.0, 1.0) * double(values.size())));
    return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
}

} // namespace renderer
