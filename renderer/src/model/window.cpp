// Window/level choices (see window.h).
#include "renderer/model/window.h"

#include "renderer/model/enum_names.h"
#include "renderer/errors.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

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
    // Nearest rank: percentile p is the element at round(p / 100 * (n - 1)) of the sorted values.
    const auto rank = [&](size_t n, double p) { return size_t(std::llround(p / 100.0 * double(n - 1))); };
    return volume.values.visit([&](const auto& values) -> ValueRange {
        using Stored = typename std::remove_cvref_t<decltype(values)>::value_type;
        if constexpr (std::is_integral_v<Stored>) {
            // Integers take at most 65536 values: count them rather than copy the volume to sort it.
            constexpr int64_t lowest = std::numeric_limits<Stored>::min();
            std::vector<uint64_t> counts(size_t(std::numeric_limits<Stored>::max() - lowest + 1), 0);
            for (const Stored v : values) ++counts[size_t(int64_t(v) - lowest)];
            if (values.empty()) return {};
            const size_t lo = rank(values.size(), loPercent), hi = rank(values.size(), hiPercent);
            ValueRange window;
            uint64_t below = 0;   // values in the bins before this one: the rank of its first element
            for (size_t bin = 0; bin < counts.size(); ++bin) {
                const uint64_t next = below + counts[bin];
                if (below <= lo && lo < next) window.lo = float(int64_t(bin) + lowest);
                if (below <= hi && hi < next) {
                    window.hi = float(int64_t(bin) + lowest);
                    break;
                }
                below = next;
            }
            return window;
        } else {
            std::vector<float> finite;
            finite.reserve(values.size());
            for (const float v : values)
                if (std::isfinite(v)) finite.push_back(v);
            if (finite.empty()) return {};
            const size_t lo = rank(finite.size(), loPercent), hi = rank(finite.size(), hiPercent);
            std::nth_element(finite.begin(), finite.begin() + std::ptrdiff_t(lo), finite.end());
            const float loValue = finite[lo];
            // Everything past `lo` is >= it, so the second selection only needs that part.
            std::nth_element(finite.begin() + std::ptrdiff_t(lo), finite.begin() + std::ptrdiff_t(hi), finite.end());
            return {loValue, finite[hi]};
        }
    });
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
