// The split view's layout, per-pane settings and difference image (split_view.h); no ImGui here.
#include "ui/split_view.h"

#include "renderer/errors.h"
#include "renderer/model/enum_names.h"
#include "renderer/math/metrics.h"

#include <algorithm>
#include <cmath>

namespace ui {

const char* splitDifferenceName(SplitDifference d) {
    switch (d) {
    case SplitDifference::Off:
        return "off";
    case SplitDifference::AgainstB:
        return "b";
    case SplitDifference::AgainstTruth:
        return "truth";
    }
    return "off";
}

SplitDifference splitDifferenceFromName(const std::string& name) {
    return renderer::enumFromName(name, {SplitDifference::Off, SplitDifference::AgainstB, SplitDifference::AgainstTruth},
                                  &splitDifferenceName, "difference");
}

SplitLayout splitLayout(int width, int height, int imagePanes, bool difference) {
    const bool grid = imagePanes == 4;
    const int columns = 2 + (difference ? 1 : 0), rows = grid ? 2 : 1;
    const int w = std::max(1, width / columns), h = std::max(1, height / rows);
    SplitLayout layout;
    for (int i = 0; i < (grid ? 4 : 2); ++i)
        layout.panes.push_back({(i % 2) * w, (i / 2) * h, w, h});
    if (difference) layout.difference = PaneRect{2 * w, grid ? h / 2 : 0, w, h};
    return layout;
}

std::vector<PaneRect> splitPaneRects(int width, int height, int imagePanes, bool difference) {
    SplitLayout layout = splitLayout(width, height, imagePanes, difference);
    if (layout.difference) layout.panes.push_back(*layout.difference);
    return layout.panes;
}

renderer::Image upsampleBilinear(const renderer::Image& image, int width, int height) {
    renderer::Image out(width, height);
    if (image.width < 1 || image.height < 1) return out;
    const double sx = double(image.width) / width, sy = double(image.height) / height;
    for (int y = 0; y < height; ++y) {
        const double fy = std::clamp((y + 0.5) * sy - 0.5, 0.0, double(image.height - 1));
        const int y0 = int(fy), y1 = std::min(y0 + 1, image.height - 1);
        const double ty = fy - y0;
        for (int x = 0; x < width; ++x) {
            const double fx = std::clamp((x + 0.5) * sx - 0.5, 0.0, double(image.width - 1));
            const int x0 = int(fx), x1 = std::min(x0 + 1, image.width - 1);
            const double tx = fx - x0;
            for (int c = 0; c < 4; ++c) {
                const double top = image.pixel(x0, y0)[c] * (1 - tx) + image.pixel(x1, y0)[c] * tx;
                const double bottom = image.pixel(x0, y1)[c] * (1 - tx) + image.pixel(x1, y1)[c] * tx;
                out.pixel(x, y)[c] = float(top * (1 - ty) + bottom * ty);
            }
        }
    }
    return out;
}

renderer::SplatSettings paneSettings(renderer::SplatSettings view, const SplitPane& pane) {
    view.filter = pane.filter;
    view.compositing = pane.compositing;
    if (pane.compositing == renderer::Compositing::SplatEverySample &&
        view.primitive == renderer::SplatSettings::Primitive::Tiles)
        view.primitive = renderer::SplatSettings::Primitive::Auto;
    return view;
}

std::string paneLabel(const SplitPane& pane) {
    return std::string(renderer::filterModeName(pane.filter)) + ", " +
           renderer::compositingName(pane.compositing);
}

std::array<uint8_t, 3> differenceColour(double t) {
    // Five stops of matplotlib's inferno, linearly interpolated.
    static constexpr std::array<std::array<double, 3>, 5> kStops{
        {{0, 0, 4}, {87, 16, 110}, {188, 55, 84}, {249, 142, 9}, {252, 255, 164}}};
    t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 1.0;
    const double at = t * double(kStops.size() - 1);
    const size_t i = std::min(size_t(at), kStops.size() - 2);
    const double f = at - double(i);
    std::array<uint8_t, 3> rgb{};
    for (size_t c = 0; c < 3; ++c)
        rgb[c] = uint8_t(std::lround(kStops[i][c] + f * (kStops[i + 1][c] - kStops[i][c])));
    return rgb;
}

double niceScaleMax(double x) {
    if (!(x > 1e-6)) return 1e-6;
    const double decade = std::pow(10.0, std::floor(std::log10(x)));
    for (double step : {1.0, 2.0, 5.0, 10.0})
        if (step * decade >= x * (1.0 - 1e-12)) return step * decade;
    return 10.0 * decade;
}

DifferencePane differencePane(const renderer::Image& a, const renderer::Image& b) {
    const renderer::ImageError error = renderer::compareImages(a, b); // throws when the sizes differ
    DifferencePane d;
    d.width = a.width, d.height = a.height;
    d.rmse = error.rmse, d.psnrDb = error.psnrDb;
    const size_t pixels = size_t(a.width) * size_t(a.height);
    std::vector<double> perPixel(pixels);
    for (size_t p = 0; p < pixels; ++p) {
        double sum = 0.0;
        for (size_t c = 0; c < 4; ++c) {
            const double diff = double(a.rgba[p * 4 + c]) - double(b.rgba[p * 4 + c]);
            sum += diff * diff;
        }
        perPixel[p] = std::sqrt(sum / 4.0);
        if (!(perPixel[p] <= d.maxError)) d.maxError = std::isfinite(perPixel[p]) ? perPixel[p] : HUGE_VAL;
    }
    // The scale's top: the 1-2-5 step over the 99th percentile of the pixels that differ at all, so that a
    // few outliers (silhouette pixels) do not leave the rest dark; larger errors take the top colour.
    std::vector<double> differing;
    for (double e : perPixel)
        if (e > 1e-6) differing.push_back(std::isfinite(e) ? e : 1.0);
    if (!differing.empty()) {
        const auto at = differing.begin() + std::ptrdiff_t(std::ceil(0.99 * double(differing.size() - 1)));
        std::nth_element(differing.begin(), at, differing.end());
        d.scaleMax = niceScaleMax(*at);
    } else {
        d.scaleMax = niceScaleMax(0.0);
    }
    d.rgba.resize(pixels * 4);
    for (size_t p = 0; p < pixels; ++p) {
        const std::array<uint8_t, 3> rgb = differenceColour(perPixel[p] / d.scaleMax);
        d.rgba[p * 4 + 0] = rgb[0], d.rgba[p * 4 + 1] = rgb[1], d.rgba[p * 4 + 2] = rgb[2],
                       d.rgba[p * 4 + 3] = 255;
    }
    return d;
}

} // namespace ui
