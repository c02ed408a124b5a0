// Window/level choices (see window.h).
#include "renderer/model/window.h"

#include "renderer/model/enum_names.h"
#include "renderer/errors.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace renderer {

const char* windowModeName(WindowMode mode) {
    switch (mode) {
    case WindowMode::DataRange:
        return "data range";
    case WindowMode::Percentile:
        return "percentile 1-99";
    case WindowMode::Custom:
        return "custom";
    }
    return "unknown";
}

WindowMode windowModeFromName(const std::string& name) {
    return enumFromName(name, {WindowMode::DataRange, WindowMode::Percentile, WindowMode::Custom}, &windowModeName,
                        "window mode");
}

ValueRange percentileWindow(const Volume& volume, double loPercent, double hiPercent) {
    if (!(loPercent >= 0 && hiPercent <= 100 && loPercent <= hiPercent))
        throw RenderError("percentileWindow: percentiles " + std::to_string(loPercent) + ".." +
                          std::to_string(hiPercent) + ", expected 0 <= lo <= hi <= 100");
    std::vector<float> finite;
    finite.reserve(volume.values.size());
    for (float v : volume.values)
        if (std::isfinite(v)) finite.push_back(v);
    if (finite.empty()) return {};
    // Nearest rank: percentile p is the element at round(p / 100 * (n - 1)) of the sorted values.
    const auto rank = [&](double p) { return size_t(std::llround(p / 100.0 * double(finite.size() - 1))); };
    const size_t lo = rank(loPercent), hi = rank(hiPercent);
    std::nth_element(finite.begin(), finite.begin() + std::ptrdiff_t(lo), finite.end());
    const float loValue = finite[lo];
    // Everything past `lo` is >= it, so the second selection only needs that part.
    std::nth_element(finite.begin() + std::ptrdiff_t(lo), finite.begin() + std::ptrdiff_t(hi), finite.end());
    return {loValue, finite[hi]};
}

ValueRange windowFor(const Volume& volume, const WindowSettings& settings) {
    switch (settings.mode) {
    case WindowMode::DataRange:
        return volume.range;
    case WindowMode::Percentile:
        return percentileWindow(volume, 1.0, 99.0);
    case WindowMode::Custom:
        if (!(std::isfinite(settings.custom.lo) && std::isfinite(settings.custom.hi) &&
              settings.custom.lo < settings.custom.hi))
            throw RenderError("custom window " + std::to_string(settings.custom.lo) + ".." +
                              std::to_string(settings.custom.hi) + ": expected finite lo < hi (data units)");
        return settings.custom;
    }
    return volume.range;
}

} // namespace renderer
