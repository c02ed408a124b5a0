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
