// Save image with the heatmap on: the heatmap over the image at the viewport's opacity, on the CPU. The
// viewport blends the same way on the GPU (ui::drawViewportPanel: heatmap x opacity + image x (1 - opacity));
// premultiplied RGBA blended so gives the same as the two composited over the background, then blended.
#pragma once
#include "renderer/io/image.h"

#include <cassert>
#include <utility>

// `opacity` 0: `image` as it is (`heatmap` may be empty); 1: `heatmap` (`image` may be empty).
inline renderer::Image blendHeatmap(renderer::Image image, renderer::Image heatmap, double opacity) {
    if (opacity <= 0.0) return image;
    if (opacity >= 1.0) return heatmap;
    assert(image.rgba.size() == heatmap.rgba.size() && "the image and its heatmap come from one render");
    const float t = float(opacity);
    for (size_t i = 0; i < image.rgba.size(); ++i)
        image.rgba[i] += t * (heatmap.rgba[i] - image.rgba[i]);
    return image;
}
