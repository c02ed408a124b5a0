// Transfer functions: the two piecewise-linear functions, the baked LUT, whole-TF edits (shift, rescale,
// window fractions to data units) and the built-in presets. JSON I/O is transfer_function_json.cpp's.
#include "renderer/model/transfer_function.h"

#include "renderer/errors.h"
#include "renderer/model/slicer_preset.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace renderer {

namespace {

ControlPoint cp(double v, double r, double g, double b, double a) { return {v, {r, g, b}, a}; }

struct Preset {
    const char* name;
    std::vector<ControlPoint> points;
};

// Built-in presets over window fractions. CT presets assume air near 0 and bone near the top.
const std::vector<Preset>& presets() {
    static const std::vector<Preset> table = {
        {"ct-skin-bone",
         {cp(0.00, 0, 0, 0, 0), cp(0.12, 0.60, 0.35, 0.25, 0), cp(0.16, 0.85, 0.60, 0.50, 0.6),
          cp(0.20, 0.85, 0.60, 0.50, 0.0), cp(0.36, 0.80, 0.75, 0.65, 0.0), cp(0.44, 0.90, 0.87, 0.80, 0.8),
          cp(1.00, 1.0, 1.0, 1.0, 1.0)}},
        {"ct-bone",
         {cp(0.00, 0, 0, 0, 0), cp(0.34, 0.9, 0.85, 0.75, 0), cp(0.42, 1.0, 0.97, 0.90, 0.7),
          cp(1.00, 1.0, 1.0, 1.0, 0.9)}},
        {"grey-ramp", {cp(0.00, 0, 0, 0, 0), cp(0.10, 0.1, 0.1, 0.1, 0), cp(1.00, 1, 1, 1, 1)}},
        {"soft",
         {cp(0.00, 0.0, 0.0, 0.0, 0), cp(0.15, 0.2, 0.3, 0.8, 0), cp(0.40, 0.3, 0.8, 0.6, 0.08),
          cp(0.70, 0.9, 0.8, 0.3, 0.2), cp(1.00, 1.0, 0.3, 0.2, 0.5)}},
        {"fire",
         {cp(0.00, 0, 0, 0, 0), cp(0.20, 0.5, 0.0, 0.0, 0), cp(0.40, 0.9, 0.3, 0.0, 0.15),
          cp(0.70, 1.0, 0.7, 0.1, 0.5), cp(1.00, 1.0, 1.0, 0.8, 0.9)}},
    };
    return table;
}

// The points around `value` in a sorted list, and how far between them: the end point's own outside.
template <class Point, class Get>
auto interpolate(const std::vector<Point>& pts, double value, Get get) {
    auto hi = std::lower_bound(pts.begin(), pts.end(), value, [](const Point& p, double x) { return p.value < x; });
    if (hi == pts.begin()) return get(*hi);
    if (hi == pts.end()) return get(pts.back());
    const Point& lo = *(hi - 1);
    const double w = (hi->value > lo.value) ? (value - lo.value) / (hi->value - lo.value) : 1.0;
    return glm::mix(get(lo), get(*hi), w);
}

} // namespace

TransferFunction fromSharedPoints(std::string name, const std::vector<ControlPoint>& points) {
    TransferFunction tf;
    tf.name = std::move(name);
    tf.windowFractions = true;
    for (const ControlPoint& p : points) {
        tf.colours.push_back({p.value, p.colour});
        tf.opacities.push_back({p.value, p.opacity});
    }
    return tf;
}

glm::dvec4 evaluate(const TransferFunction& tf, double value) {
    const glm::dvec3 colour = tf.colours.empty()
                                  ? glm::dvec3(0.0)
                                  : interpolate(tf.colours, value, [](const ColourPoint& p) { return p.colour; });
    const double opacity = tf.opacities.empty()
                               ? 0.0
                               : interpolate(tf.opacities, value, [](const OpacityPoint& p) { return p.opacity; });
    return glm::dvec4(colour, opacity);
}

double evaluateGradientOpacity(const TransferFunction& tf, double magnitude) {
    if (tf.gradientOpacity.empty()) return 1.0;
    const auto& pts = tf.gradientOpacity;
    auto hi = std::lower_bound(pts.begin(), pts.end(), magnitude,
                               [](const GradientOpacityPoint& p, double x) { return p.magnitude < x; });
    if (hi == pts.begin()) return hi->opacity;
    if (hi == pts.end()) return pts.back().opacity;
    const GradientOpacityPoint& lo = *(hi - 1);
    const double w = (hi->magnitude > lo.magnitude) ? (magnitude - lo.magnitude) / (hi->magnitude - lo.magnitude) : 1.0;
    return lo.opacity + (hi->opacity - lo.opacity) * w;
}

double widgetWeight(const Widget2D& w, double value, double magnitude) {
    if (w.shape == WidgetShape::Rectangle)
        return value >= w.valueLo && value <= w.valueHi && magnitude >= w.magnitudeLo && magnitude <= w.magnitudeHi
                   ? 1.0
                   : 0.0;
    if (!(magnitude >= 0.0) || !(magnitude <= w.magnitudeTop) || !(w.magnitudeTop > 0.0)) return 0.0;
    const double half = w.halfWidth * magnitude / w.magnitudeTop;   // the half-width at this magnitude
    const double off = std::abs(value - w.apex);
    if (!(half > 0.0)) return off == 0.0 ? 1.0 : 0.0;                // the apex itself
    return std::max(0.0, 1.0 - off / half);
}

glm::dvec4 evaluate2d(const TransferFunction& tf, double value, double magnitude) {
    double opacity = 0.0, weights = 0.0;
    glm::dvec3 colour(0.0);
    for (const Widget2D& w : tf.widgets2d) {
        const double a = widgetWeight(w, value, magnitude) * w.opacity;
        if (!(a > 0.0)) continue;
        opacity = std::max(opacity, a);
        colour += a * w.colour;
        weights += a;
    }
    return glm::dvec4(weights > 0.0 ? colour / weights : glm::dvec3(0.0), opacity);
}

Lut bakeLut(const TransferFunction& tf, ValueRange window) {
    Lut lut(kLutSize, glm::vec4(0.0f));
    const double lo = window.lo, span = double(window.hi) - double(window.lo);
    for (int i = 0; i < kLutSize; ++i) {
        const double t = (i + 0.5) / kLutSize;   // the middle of class i, as a fraction of the window
        lut[size_t(i)] = glm::vec4(evaluate(tf, tf.windowFractions ? t : lo + t * span));
    }
    return lut;
}

uint16_t classOf(float value, float lo, float hi) {
    if (!(hi > lo) || !std::isfinite(value)) return 0;
    const double t = (double(value) - lo) / (double(hi) - lo);
    return uint16_t(std::clamp(int(std::floor(t * kLutSize)), 0, kLutSize - 1));
}

TransferFunction inDataUnits(const TransferFunction& tf, ValueRange window) {
    if (!tf.windowFractions || !(window.hi > window.lo)) return tf;
    TransferFunction out = tf;
    out.windowFractions = false;
    const double lo = window.lo, hi = window.hi;
    // lo * (1 - t) + hi * t: exactly lo at 0 and hi at 1, so the TF's ends stay on the window's.
    const auto toData = [&](double t) { return lo * (1.0 - t) + hi * t; };
    for (auto& p : out.colours) p.value = toData(p.value);
    for (auto& p : out.opacities) p.value = toData(p.value);
    return out;
}

TfExtent extentOf(const TransferFunction& tf) {
    if (tf.colours.empty() && tf.opacities.empty() && tf.widgets2d.empty()) return {};
    TfExtent e{INFINITY, -INFINITY};
    const auto add = [&](double v) { e.lo = std::min(e.lo, v), e.hi = std::max(e.hi, v); };
    for (const auto& p : tf.colours) add(p.value);
    for (const auto& p : tf.opacities) add(p.value);
    for (const auto& w : tf.widgets2d) {
        if (w.shape == WidgetShape::Rectangle) add(w.valueLo), add(w.valueHi);
        else add(w.apex - w.halfWidth), add(w.apex + w.halfWidth);
    }
    return e;
}

TransferFunction shifted(const TransferFunction& tf, double offset) {
    TransferFunction out = tf;
    for (auto& p : out.colours) p.value += offset;
    for (auto& p : out.opacities) p.value += offset;
    for (auto& w : out.widgets2d) w.valueLo += offset, w.valueHi += offset, w.apex += offset;
    return out;
}

TransferFunction rescaled(const TransferFunction& tf, double lo, double hi) {
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo))
        throw RenderError("cannot rescale a transfer function onto " + std::to_string(lo) + " .. " +
                          std::to_string(hi) + ": expected finite ends, low below high");
    const TfExtent from = extentOf(tf);
    if (!(from.hi > from.lo)) return shifted(tf, 0.5 * (lo + hi) - from.lo);
    TransferFunction out = tf;
    const double scale = (hi - lo) / (from.hi - from.lo);
    // The ends land exactly on lo and hi; the rest in proportion.
    const auto map = [&](double v) { return v == from.hi ? hi : v == from.lo ? lo : lo + (v - from.lo) * scale; };
    for (auto& p : out.colours) p.value = map(p.value);
    for (auto& p : out.opacities) p.value = map(p.value);
    for (auto& w : out.widgets2d) {
        w.valueLo = map(w.valueLo), w.valueHi = map(w.valueHi);
        w.apex = lo + (w.apex - from.lo) * scale, w.halfWidth *= scale;
    }
    return out;
}

// The bundled preset files, NAME.json in the assets' presets folder, by name, sorted; a file named like
// a preset in code is left out (the code's wins). Read at each call: the folder is small, and a file a
// user adds there is a preset at once.
std::vector<std::pair<std::string, std::filesystem::path>> bundledPresetFiles() {
    std::vector<std::pair<std::string, std::filesystem::path>> files;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(SPLATLAB_ASSET_DIR "/presets", ec)) {
        const std::filesystem::path& path = entry.path();
        if (path.extension() != ".json" || !entry.is_regular_file(ec)) continue;
        const std::string name = path.stem().string();
        if (std::none_of(presets().begin(), presets().end(), [&](const Preset& p) { return name == p.name; }))
            files.emplace_back(name, path);
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::vector<std::string> builtinPresetNames() {
    std::vector<std::string> names;
    for (const auto& p : presets()) names.push_back(p.name);
    for (const auto& [name, path] : bundledPresetFiles()) names.push_back(name);
    return names;
}

TransferFunction builtinPreset(const std::string& name) {
    for (const auto& p : presets())
        if (name == p.name) return fromSharedPoints(p.name, p.points);
    for (const auto& [fileName, path] : bundledPresetFiles())
        if (name == fileName) return loadTransferFunction(path);
    std::string known;
    for (const auto& n : builtinPresetNames()) known += (known.empty() ? "" : ", ") + n;
    throw RenderError("unknown transfer-function preset '" + name + "' (known: " + known + ")");
}

TransferFunction transferFunctionFromSpec(const std::string& spec, std::vector<std::string>* notes) {
    for (const auto& n : builtinPresetNames())
        if (spec == n) return builtinPreset(spec);
    if (const std::optional<SlicerPresetSpec> slicer = slicerPresetSpec(spec)) {
        LoadedSlicerPreset loaded = loadSlicerPreset(*slicer);
        if (notes) notes->insert(notes->end(), loaded.notes.begin(), loaded.notes.end());
        return std::move(loaded.preset.tf);
    }
    if (spec.ends_with(".json") || std::filesystem::exists(spec)) return loadTransferFunction(spec);
    return builtinPreset(spec);   // throws, listing the known names
}

} // namespace renderer
