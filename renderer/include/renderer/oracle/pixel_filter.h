// The V_h pixel filter of the ground truth (EWA_NOTES "Ground truth"), one place for the truth and the
// supersampled image-aligned slabs: a grid of `ss` x `ss` samples a pixel, `pixelFilterMargin(ss)`
// samples more on each side, sample i at pixel coordinate (i - margin + 0.5) / ss; each pixel is the
// mean of the samples within kPixelFilterReachPx of its centre, weighted by the 1-px Gaussian.
#pragma once
#include "renderer/io/image.h"
#include "renderer/math/camera.h"
#include "renderer/math/glm_config.h"

#include <functional>

#include <vector>

namespace renderer {

constexpr double kPixelFilterReachPx = 4.0;   // the 1-px Gaussian's weight beyond 4 sigma is below 3.4e-4
int pixelFilterMargin(int ss);

// samples: (width ss + 2 margin) x (height ss + 2 margin), rows first. Separable, on all cores.
Image filterToPixels(const std::vector<glm::dvec4>& samples, int ss, int width, int height);

// `render` on the finer plane of that sample grid (ss times the pixels, the margin around), resolved by
// the filter to `plane`'s pixels; ss 0: render(plane) as it is.
Image renderSupersampled(const ImagePlane& plane, int ss, const std::function<Image(const ImagePlane&)>& render);

} // namespace renderer
