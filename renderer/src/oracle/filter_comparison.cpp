// Filter cost beside error (filter_comparison.h).
#include "renderer/oracle/filter_comparison.h"

#include "renderer/oracle/accuracy.h"
#include "renderer/math/metrics.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace renderer {

ImagePlane centreCrop(const ImagePlane& view, int side) {
    const int w = std::min(side, view.width), h = std::min(side, view.height);
    return cropPlane(view, (view.width - w) / 2, (view.height - h) / 2, w, h);
}

FilterMeasurement measureFilter(SplatRenderer& gl, const ImagePlane& view, const ImagePlane& crop,
                                const Image& cropTruth, SplatSettings settings, FilterMode filter, int frames) {
    settings.filter = filter;
    settings.heatmap = false;
    settings.counters = false;   // counting waits for each frame: it would be timed too
    gl.render(view, settings);   // compiles what this filter needs
    glFinish();
    std::vector<double> ms;
    for (int i = 0; i < std::max(frames, 1); ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        gl.render(view, settings);
        glFinish();
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::nth_element(ms.begin(), ms.begin() + ptrdiff_t(ms.size() / 2), ms.end());
    const ImageError e = cropError(gl, crop, cropTruth, settings);
    return {filter, ms[ms.size() / 2], e.rmse, e.psnrDb};
}

ImageError cropError(SplatRenderer& gl, const ImagePlane& crop, const Image& cropTruth, const SplatSettings& settings) {
    gl.render(crop, settings);
    return compareImages(gl.readback(), cropTruth);
}

} // namespace renderer
