// ParaView colour-map presets in and out (paraview_preset.h).
#include "renderer/model/paraview_preset.h"

#include "renderer/errors.h"
#include "renderer/io/atomic_file.h"
#include "renderer/io/json_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace renderer {

namespace {

// A flat array of numbers in groups of four, each finite.
std::vector<double> quadruples(const nlohmann::json& preset, const char* key, const std::string& source) {
    const nlohmann::json& v = preset[key];
    if (!v.is_array() || v.empty() || v.size() % 4 != 0)
        throw LoadError(source, key, "expected a non-empty array of numbers in groups of 4, got " + std::to_string(
                                         v.is_array() ? v.size() : 0) + " values");
    std::vector<double> out;
    for (size_t i = 0; i < v.size(); ++i) {
        if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
            throw LoadError(source, std::string(key) + "[" + std::to_string(i) + "]",
                            v[i].dump().substr(0, 80) + ", expected a finite number");
        out.push_back(v[i].get<double>());
    }
    return out;
}

void inUnitRange(double x, const std::string& source, const std::string& field) {
    if (x < 0.0 || x > 1.0) throw LoadError(source, field, std::to_string(x) + ", expected [0,1]");
}

} // namespace

TransferFunction transferFunctionFromParaView(const nlohmann::json& j, const std::string& source) {
    const nlohmann::json* preset = &j;
    if (j.is_array()) {
        if (j.empty()) throw LoadError(source, "", "an empty preset list");
        preset = &j[0];
    }
    if (!preset->is_object()) throw LoadError(source, "", "expected a ParaView preset (a JSON object or a list of them)");
    TransferFunction tf;
    tf.name = preset->contains("Name") && (*preset)["Name"].is_string() ? (*preset)["Name"].get<std::string>() : "paraview";
    if (preset->contains("ColorSpace") && (*preset)["ColorSpace"] != "RGB")
        throw LoadError(source, "ColorSpace",
                        (*preset)["ColorSpace"].dump().substr(0, 80) +
                            ", only \"RGB\" is read (colours linear between the stops, as SplatLab interpolates)");
    if (!preset->contains("RGBPoints")) throw LoadError(source, "RGBPoints", "missing");
    const std::vector<double> rgb = quadruples(*preset, "RGBPoints", source);
    for (size_t i = 0; i < rgb.size(); i += 4) {
        for (size_t c = 1; c < 4; ++c) inUnitRange(rgb[i + c], source, "RGBPoints[" + std::to_string(i + c) + "]");
        tf.colours.push_back({rgb[i], {rgb[i + 1], rgb[i + 2], rgb[i + 3]}});
    }
    if (preset->contains("Points")) {
        const std::vector<double> pts = quadruples(*preset, "Points", source);
        for (size_t i = 0; i < pts.size(); i += 4) {
            inUnitRange(pts[i + 1], source, "Points[" + std::to_string(i + 1) + "]");
            if (pts[i + 2] != 0.5 || pts[i + 3] != 0.0)
                throw LoadError(source, "Points[" + std::to_string(i + 2) + "]",
                                "midpoint " + std::to_string(pts[i + 2]) + " and sharpness " + std::to_string(pts[i + 3]) +
                                    ", only 0.5 and 0 (linear) are read");
            tf.opacities.push_back({pts[i], pts[i + 1]});
        }
    } else {
        const auto [lo, hi] = std::minmax_element(tf.colours.begin(), tf.colours.end(),
                                                  [](const ColourPoint& a, const ColourPoint& b) { return a.value < b.value; });
        tf.opacities = {{lo->value, 0.0}, {hi->value, 1.0}};
    }
    const auto byValue = [](const auto& a, const auto& b) { return a.value < b.value; };
    std::stable_sort(tf.colours.begin(), tf.colours.end(), byValue);
    std::stable_sort(tf.opacities.begin(), tf.opacities.end(), byValue);
    return tf;
}

TransferFunction loadParaViewPreset(const std::filesystem::path& path) {
    return transferFunctionFromParaView(readJsonFile(path, "a ParaView preset (.json)"), path.string());
}

nlohmann::json toParaView(const TransferFunction& tf) {
    nlohmann::json preset;
    preset["Name"] = tf.name;
    preset["ColorSpace"] = "RGB";
    preset["RGBPoints"] = nlohmann::json::array();
    for (const ColourPoint& p : tf.colours)
        for (double x : {p.value, p.colour.r, p.colour.g, p.colour.b}) preset["RGBPoints"].push_back(x);
    preset["Points"] = nlohmann::json::array();
    for (const OpacityPoint& p : tf.opacities)
        for (double x : {p.value, p.opacity, 0.5, 0.0}) preset["Points"].push_back(x);
    return nlohmann::json::array({preset});
}

std::string paraViewPresetText(const TransferFunction& tf) { return toParaView(tf).dump(2) + "\n"; }

void saveParaViewPreset(const TransferFunction& tf, const std::filesystem::path& path) {
    writeFileAtomically(path, paraViewPresetText(tf));
}

} // namespace renderer
