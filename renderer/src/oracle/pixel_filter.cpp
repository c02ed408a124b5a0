// The ground truth's V_h pixel filter (see pixel_filter.h).
#include "renderer/oracle/pixel_filter.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <utility>

namespace renderer {

int pixelFilterMargin(int ss) { return int(std::ceil(kPixelFilterReachPx * ss)); }

namespace {

// filterToPixels over any store of samples: `sample(i)` is sample i of the grid, rows first, as a dvec4.
template <class Sample>
Image filterSamples(const Sample& sample, int ss, int width, int height) {
    const int margin = pixelFilterMargin(ss);
    const int gw = width * ss + 2 * margin, gh = height * ss + 2 * margin;
    // Weights exp(-d^2/2) of each sample's distance d (pixels) from the pixel centre, normalised over
    // the samples within reach.
    const auto weightsFor = [&](int pixel, int count) {
        std::vector<std::pair<int, double>> w;
        double sum = 0.0;
        for (int i = 0; i < count; ++i) {
            const double d = (i - margin + 0.5) / ss - (pixel + 0.5);
            if (std::abs(d) <= kPixelFilterReachPx) w.emplace_back(i, std::exp(-0.5 * d * d)), sum += w.back().second;
        }
        for (auto& [i, v] : w) v /= sum;
        return w;
    };
    std::vector<glm::dvec4> rows(size_t(width) * gh);
    tbb::parallel_for(0, width, [&](int x) {
        const auto w = weightsFor(x, gw);
        for (int j = 0; j < gh; ++j) {
            glm::dvec4 acc(0.0);
            for (auto [i, v] : w) acc += v * sample(size_t(j) * gw + size_t(i));
            rows[size_t(j) * width + x] = acc;
        }
    });
    Image img(width, height);
    tbb::parallel_for(0, height, [&](int y) {
        const auto w = weightsFor(y, gh);
        for (int x = 0; x < width; ++x) {
            glm::dvec4 acc(0.0);
            for (auto [j, v] : w) acc += v * rows[size_t(j) * width + x];
            float* out = img.pixel(x, y);
            for (int c = 0; c < 4; ++c) out[c] = float(acc[c]);
        }
    });
    return img;
}

} // namespace

Image filterToPixels(const std::vector<glm::dvec4>& samples, int ss, int width, int height) {
    return filterSamples([&](size_t i) { return samples[i]; }, ss, width, height);
}

Image renderSupersampled(const ImagePlane& plane, int ss, const std::function<Image(const ImagePlane&)>& render) {
    if (ss == 0) return render(plane);
    const int margin = pixelFilterMargin(ss);
    ImagePlane fine = plane;
    fine.width = plane.width * ss + 2 * margin;
    fine.height = plane.height * ss + 2 * margin;
    fine.fPx = plane.fPx * ss;
    fine.centrePx = plane.centrePx * double(ss) + double(margin);
    const Image samples = render(fine);
    // Read in place: a double copy of the fine grid would be twice its size again (132 MiB at 512x512, 4x4).
    const float* rgba = samples.rgba.data();
    return filterSamples([rgba](size_t i) { return glm::dvec4(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2], rgba[4 * i + 3]); },
                         ss, plane.width, plane.height);
}

} // namespace renderer
