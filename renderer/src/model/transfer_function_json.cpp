// Transfer-function files: version 2 (colour and opacity points of their own, in data units) written,
// versions 1 (shared points, window fractions) and 2 read. docs/formats.md describes both.
#include "renderer/model/transfer_function.h"

#include "renderer/errors.h"
#include "renderer/io/atomic_file.h"
#include "renderer/io/json_file.h"
#include "renderer/model/paraview_preset.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace renderer {

namespace {

// The format written; a file of a later one is refused rather than half read.
constexpr int kTransferFunctionVersion = 2;
constexpr const char* kDataUnits = "data";
constexpr const char* kWindowFractions = "window fraction";

// Reads the fields of one file, each error naming the file and the field (e.g. "opacity[2].value").
struct TfReader {
    const std::string& source;

    [[noreturn]] void fail(const std::string& field, const std::string& why) const {
        throw LoadError(source, field, why);
    }
    double number(const nlohmann::json& j, const std::string& field, const char* key, bool unitRange) const {
        if (!j.is_object() || !j.contains(key)) fail(field + "." + key, "missing");
        const nlohmann::json& v = j[key];
        if (!v.is_number()) fail(field + "." + key, v.dump() + ", expected a number");
        const double x = v.get<double>();
        if (!std::isfinite(x)) fail(field + "." + key, "is not finite");
        if (unitRange && (x < 0.0 || x > 1.0)) fail(field + "." + key, std::to_string(x) + ", expected [0,1]");
        return x;
    }
    glm::dvec3 rgb(const nlohmann::json& j, const std::string& field, const char* key) const {
        if (!j.is_object() || !j.contains(key)) fail(field + "." + key, "missing");
        const nlohmann::json& v = j[key];
        if (!v.is_array() || v.size() != 3)
            fail(field + "." + key, v.dump().substr(0, 80) + ", expected 3 numbers (r, g, b) in [0,1]");
        glm::dvec3 c;
        for (int i = 0; i < 3; ++i) {
            if (!v[size_t(i)].is_number()) fail(field + "." + key, "has " + v[size_t(i)].dump() + ", expected numbers");
            c[i] = v[size_t(i)].get<double>();
            if (!std::isfinite(c[i]) || c[i] < 0.0 || c[i] > 1.0)
                fail(field + "." + key, "a value is " + std::to_string(c[i]) + ", expected [0,1]");
        }
        return c;
    }
    const nlohmann::json& list(const nlohmann::json& j, const char* key, const char* what) const {
        if (!j.contains(key) || !j[key].is_array())
            fail(key, std::string("missing, expected an array of ") + what);
        if (j[key].empty()) fail(key, std::string("has no control points, expected at least 1 ") + what);
        return j[key];
    }
};

void sortPoints(TransferFunction& tf) {
    const auto byValue = [](const auto& a, const auto& b) { return a.value < b.value; };
    std::stable_sort(tf.colours.begin(), tf.colours.end(), byValue);
    std::stable_sort(tf.opacities.begin(), tf.opacities.end(), byValue);
    std::stable_sort(tf.gradientOpacity.begin(), tf.gradientOpacity.end(),
                     [](const auto& a, const auto& b) { return a.magnitude < b.magnitude; });
}

// Optional in either version: "gradientOpacity": [{magnitude, opacity}], magnitudes in data units per
// world unit (>= 0). Absent: no gradient opacity, so every file from before it reads as it did.
void readGradientOpacity(const nlohmann::json& j, const TfReader& in, TransferFunction& tf) {
    if (!j.contains("gradientOpacity")) return;
    const nlohmann::json& points = in.list(j, "gradientOpacity", "{magnitude, opacity}");
    for (size_t i = 0; i < points.size(); ++i) {
        const std::string field = "gradientOpacity[" + std::to_string(i) + "]";
        const double magnitude = in.number(points[i], field, "magnitude", false);
        if (magnitude < 0.0)
            in.fail(field + ".magnitude", std::to_string(magnitude) + ", expected a gradient magnitude >= 0");
        tf.gradientOpacity.push_back({magnitude, in.number(points[i], field, "opacity", true)});
    }
}

// A pair [lo, hi] of finite numbers, lo <= hi (and lo >= 0 when `magnitudes`).
std::pair<double, double> readRange(const nlohmann::json& j, const TfReader& in, const std::string& field,
                                    const char* key, bool magnitudes) {
    const std::string name = field + "." + key;
    if (!j.contains(key)) in.fail(name, "missing");
    const nlohmann::json& v = j[key];
    const char* expected = magnitudes ? ", expected [low, high] magnitudes, 0 <= low <= high"
                                      : ", expected [low, high] values, low <= high";
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
        in.fail(name, v.dump().substr(0, 80) + expected);
    const double lo = v[0].get<double>(), hi = v[1].get<double>();
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi) || (magnitudes && lo < 0.0))
        in.fail(name, v.dump().substr(0, 80) + expected);
    return {lo, hi};
}

// Optional, version 2: "widgets2d": [{shape, ..., rgb[3], opacity}], the 2D transfer function (Widget2D):
// a rectangle gives "value" and "magnitude" ranges, a triangle "apex", "halfWidth" (> 0) and
// "magnitudeTop" (> 0). Values in data units whatever "units" says; magnitudes per world unit.
void readWidgets2d(const nlohmann::json& j, const TfReader& in, TransferFunction& tf, long long version) {
    if (!j.contains("widgets2d")) return;
    if (version < 2) in.fail("widgets2d", "needs a version 2 file (\"version\": 2)");
    const nlohmann::json& widgets = j["widgets2d"];
    if (!widgets.is_array()) in.fail("widgets2d", widgets.dump().substr(0, 80) + ", expected an array of widgets");
    for (size_t i = 0; i < widgets.size(); ++i) {
        const std::string field = "widgets2d[" + std::to_string(i) + "]";
        const nlohmann::json& w = widgets[i];
        if (!w.is_object()) in.fail(field, w.dump().substr(0, 80) + ", expected an object");
        Widget2D widget;
        const nlohmann::json shape = w.contains("shape") ? w["shape"] : nlohmann::json();
        if (shape == "rectangle") {
            widget.shape = WidgetShape::Rectangle;
            std::tie(widget.valueLo, widget.valueHi) = readRange(w, in, field, "value", false);
            std::tie(widget.magnitudeLo, widget.magnitudeHi) = readRange(w, in, field, "magnitude", true);
        } else if (shape == "triangle") {
            widget.shape = WidgetShape::Triangle;
            widget.apex = in.number(w, field, "apex", false);
            widget.halfWidth = in.number(w, field, "halfWidth", false);
            if (!(widget.halfWidth > 0.0))
                in.fail(field + ".halfWidth", std::to_string(widget.halfWidth) + ", expected a width > 0");
            widget.magnitudeTop = in.number(w, field, "magnitudeTop", false);
            if (!(widget.magnitudeTop > 0.0))
                in.fail(field + ".magnitudeTop", std::to_string(widget.magnitudeTop) + ", expected a magnitude > 0");
        } else {
            in.fail(field + ".shape", (shape.is_null() ? std::string("missing") : shape.dump().substr(0, 80)) +
                                          ", expected \"rectangle\" or \"triangle\"");
        }
        widget.colour = in.rgb(w, field, "rgb");
        widget.opacity = in.number(w, field, "opacity", true);
        tf.widgets2d.push_back(widget);
    }
}

// Version 1: {"points": [{value, colour[3], opacity}]}, values 0..1 of the window.
void readVersion1(const nlohmann::json& j, const TfReader& in, TransferFunction& tf) {
    tf.windowFractions = true;
    const nlohmann::json& points = in.list(j, "points", "{value, colour[3], opacity}");
    for (size_t i = 0; i < points.size(); ++i) {
        const std::string field = "points[" + std::to_string(i) + "]";
        const double value = in.number(points[i], field, "value", true);
        tf.colours.push_back({value, in.rgb(points[i], field, "colour")});
        tf.opacities.push_back({value, in.number(points[i], field, "opacity", true)});
    }
}

// Version 2: {"units", "colour": [{value, rgb[3]}], "opacity": [{value, opacity}]} (+ readGradientOpacity).
void readVersion2(const nlohmann::json& j, const TfReader& in, TransferFunction& tf) {
    if (j.contains("units")) {
        const nlohmann::json& units = j["units"];
        if (units == kDataUnits) tf.windowFractions = false;
        else if (units == kWindowFractions) tf.windowFractions = true;
        else in.fail("units", units.dump().substr(0, 80) + ", expected \"data\" or \"window fraction\"");
    }
    const bool fractions = tf.windowFractions;
    const nlohmann::json& colours = in.list(j, "colour", "{value, rgb[3]}");
    for (size_t i = 0; i < colours.size(); ++i) {
        const std::string field = "colour[" + std::to_string(i) + "]";
        tf.colours.push_back({in.number(colours[i], field, "value", fractions), in.rgb(colours[i], field, "rgb")});
    }
    const nlohmann::json& opacities = in.list(j, "opacity", "{value, opacity}");
    for (size_t i = 0; i < opacities.size(); ++i) {
        const std::string field = "opacity[" + std::to_string(i) + "]";
        tf.opacities.push_back(
            {in.number(opacities[i], field, "value", fractions), in.number(opacities[i], field, "opacity", true)});
    }
}

} // namespace

nlohmann::json toJson(const TransferFunction& tf) {
    nlohmann::json j;
    j["version"] = kTransferFunctionVersion;
    j["name"] = tf.name;
    j["units"] = tf.windowFractions ? kWindowFractions : kDataUnits;
    j["colour"] = nlohmann::json::array();
    for (const auto& p : tf.colours) j["colour"].push_back({{"value", p.value}, {"rgb", {p.colour.r, p.colour.g, p.colour.b}}});
    j["opacity"] = nlohmann::json::array();
    for (const auto& p : tf.opacities) j["opacity"].push_back({{"value", p.value}, {"opacity", p.opacity}});
    // Only when set: a TF without it writes the text it always did.
    for (const auto& p : tf.gradientOpacity)
        j["gradientOpacity"].push_back({{"magnitude", p.magnitude}, {"opacity", p.opacity}});
    for (const auto& w : tf.widgets2d) {
        nlohmann::json o;
        if (w.shape == WidgetShape::Rectangle) {
            o["shape"] = "rectangle";
            o["value"] = {w.valueLo, w.valueHi};
            o["magnitude"] = {w.magnitudeLo, w.magnitudeHi};
        } else {
            o["shape"] = "triangle";
            o["apex"] = w.apex;
            o["halfWidth"] = w.halfWidth;
            o["magnitudeTop"] = w.magnitudeTop;
        }
        o["rgb"] = {w.colour.r, w.colour.g, w.colour.b};
        o["opacity"] = w.opacity;
        j["widgets2d"].push_back(o);
    }
    return j;
}

TransferFunction transferFunctionFromJson(const nlohmann::json& j, const std::string& source,
                                          const std::string& defaultName) {
    const TfReader in{source};
    if (!j.is_object()) in.fail("", "expected a JSON object");
    long long version = 1;   // files from before the version field are version 1
    if (j.contains("version")) {
        const nlohmann::json& v = j["version"];
        if (!v.is_number_integer() || v.get<long long>() < 1)
            in.fail("version", v.dump() + ", expected a whole number >= 1");
        version = v.get<long long>();
        if (version > kTransferFunctionVersion)
            in.fail("version", v.dump() + " is newer than this SplatLab reads (" +
                                   std::to_string(kTransferFunctionVersion) + ")");
    }
    TransferFunction tf;
    tf.name = defaultName;
    if (j.contains("name")) {
        if (!j["name"].is_string()) in.fail("name", j["name"].dump().substr(0, 80) + ", expected a string");
        tf.name = j["name"].get<std::string>();
    }
    if (version == 1) readVersion1(j, in, tf);
    else readVersion2(j, in, tf);
    readGradientOpacity(j, in, tf);
    readWidgets2d(j, in, tf, version);
    sortPoints(tf);
    return tf;
}

TransferFunction loadTransferFunction(const std::filesystem::path& path) {
    const nlohmann::json j = readJsonFile(path, "a transfer function (.json)");
    // A ParaView preset (a list of presets, or one with "RGBPoints") is imported.
    if (j.is_array() || (j.is_object() && j.contains("RGBPoints"))) return transferFunctionFromParaView(j, path.string());
    return transferFunctionFromJson(j, path.string(), path.stem().string());
}

std::string transferFunctionText(const TransferFunction& tf) { return toJson(tf).dump(2) + "\n"; }

void saveTransferFunction(const TransferFunction& tf, const std::filesystem::path& path) {
    writeFileAtomically(path, transferFunctionText(tf));
}

} // namespace renderer
