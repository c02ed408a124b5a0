// Setting cost beside error (filter_comparison.h).
#include "renderer/oracle/filter_comparison.h"

#include "renderer/errors.h"
#include "renderer/math/metrics.h"
#include "renderer/oracle/accuracy.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace renderer {

ImagePlane centreCrop(const ImagePlane& view, int side) {
    const int w = std::min(side, view.width), h = std::min(side, view.height);
    return cropPlane(view, (view.width - w) / 2, (view.height - h) / 2, w, h);
}

double percentile(std::vector<double> values, double q) {
    if (values.empty()) throw RenderError("percentile: no values");
    std::sort(values.begin(), values.end());
    const double rank = std::clamp(q, 0.0, 1.0) * double(values.size() - 1);
    const size_t below = size_t(std::floor(rank)), above = std::min(below + 1, values.size() - 1);
    return values[below] + (rank - double(below)) * (values[above] - values[below]);
}

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A setting's timed frames and its crop's error, as a measurement.
FilterMeasurement measurement(const SplatSettings& settings, const std::vector<double>& ms, const ImageError& e) {
    FilterMeasurement m;
    m.filter = settings.filter;
    m.compositing = settings.compositing;
    m.frameMs = percentile(ms, 0.5);
    m.p10Ms = percentile(ms, 0.1);
    m.p90Ms = percentile(ms, 0.9);
    m.frames = int(ms.size());
    m.rmse = e.rmse;
    m.psnrDb = e.psnrDb;
    return m;
}

} // namespace

FilterMeasurement measureSetting(SplatRenderer& gl, const ImagePlane& view, const ImagePlane& crop,
                                 const Image& cropTruth, SplatSettings settings, int frames) {
    settings.heatmap = false;
    settings.counters = false; // counting waits for each frame: it would be timed too
    gl.render(view, settings); // compiles what this setting needs
    glFinish();
    std::vector<double> ms;
    for (int i = 0; i < std::max(frames, 1); ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        gl.render(view, settings);
        glFinish();
        ms.push_back(msSince(t0));
    }
    return measurement(settings, ms, cropError(gl, crop, cropTruth, settings));
}

FilterMeasurement measureSlabs(const std::function<Image(const ImagePlane&)>& drawSlabs, const ImagePlane& view,
                               const ImagePlane& crop, const Image& cropTruth, const SplatSettings& settings,
                               const SlabOptions& slabs, int frames) {
    std::vector<double> ms;
    for (int i = 0; i < std::max(frames, 1); ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        drawSlabs(view);
        ms.push_back(msSince(t0));
    }
    FilterMeasurement m = measurement(settings, ms, compareImages(drawSlabs(crop), cropTruth));
    m.slabThickness = slabs.thickness;
    m.postClassified = slabs.postClassified;
    return m;
}

ImageError cropError(SplatRenderer& gl, const ImagePlane& crop, const Image& cropTruth,
                     const SplatSettings& settings) {
    gl.render(crop, settings);
    return compareImages(gl.readback(), cropTruth);
}

} // namespace renderer
