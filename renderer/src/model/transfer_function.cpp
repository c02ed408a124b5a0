// Transfer functions: piecewise-linear control points, the baked LUT, built-in presets and JSON I/O.
#include "renderer/model/transfer_function.h"

#include "renderer/io/atomic_file.h"
#include "renderer/errors.h"
#include "renderer/io/json_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace renderer {

namespace {

ControlPoint cp(double v, double r, double g, double b, double a) { return {v, {r, g, b}, a}; }

struct Preset {
    const char* name;
    std::vector<ControlPoint> points;
};

// Built-in presets over the normalised domain. CT presets assume air near 0 and bone near the top.
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

std::string validate(TransferFunction& tf) {
    if (tf.points.empty()) return "has no control points, expected at least 1";
    for (const auto& p : tf.points) {
        auto finite01 = [](double x) { return std::isfinite(x) && x >= 0.0 && x <= 1.0; };
        if (!finite01(p.value)) return "a point's value is " + std::to_string(p.value) + ", expected [0,1]";
        if (!finite01(p.opacity)) return "a point's opacity is " + std::to_string(p.opacity) + ", expected [0,1]";
        if (!finite01(p.colour.r) || !finite01(p.colour.g) || !finite01(p.colour.b))
            return "a point's colour is outside [0,1]";
    }
    std::stable_sort(tf.points.begin(), tf.points.end(),
                     [](const ControlPoint& a, const ControlPoint& b) { return a.value < b.value; });
    return {};
}

} // namespace

glm::dvec4 evaluate(const TransferFunction& tf, double value) {
    const auto& pts = tf.points;
    if (pts.empty()) return glm::dvec4(0.0);
    auto hi = std::lower_bound(pts.begin(), pts.end(), value,
                               [](const ControlPoint& p, double x) { return p.value < x; });
    if (hi == pts.begin()) return glm::dvec4(hi->colour, hi->opacity);
    if (hi == pts.end()) return glm::dvec4(pts.back().colour, pts.back().opacity);
    const auto& lo = *(hi - 1);
    const double w = (hi->value > lo.value) ? (value - lo.value) / (hi->value - lo.value) : 1.0;
    return glm::mix(glm::dvec4(lo.colour, lo.opacity), glm::dvec4(hi->colour, hi->opacity), w);
}

Lut bakeLut(const TransferFunction& tf) {
    Lut lut(kLutSize, glm::vec4(0.0f));
    for (int i = 0; i < kLutSize; ++i)
        lut[i] = glm::vec4(evaluate(tf, (i + 0.5) / kLutSize));   // the value at the centre of class i
    return lut;
}

uint16_t classOf(float value, float lo, float hi) {
    if (!(hi > lo) || !std::isfinite(value)) return 0;
    const double t = (double(value) - lo) / (double(hi) - lo);
    return uint16_t(std::clamp(int(std::floor(t * kLutSize)), 0, kLutSize - 1));
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
        if (name == p.name) return {p.name, p.points};
    for (const auto& [fileName, path] : bundledPresetFiles())
        if (name == fileName) return loadTransferFunction(path);
    std::string known;
    for (const auto& n : builtinPresetNames()) known += (known.empty() ? "" : ", ") + n;
    throw RenderError("unknown transfer-function preset '" + name + "' (known: " + known + ")");
}

// The format written; a file of a later one is refused rather than half read.
constexpr int kTransferFunctionVersion = 1;

nlohmann::json toJson(const TransferFunction& tf) {
    nlohmann::json j;
    j["version"] = kTransferFunctionVersion;
    j["name"] = tf.name;
    j["points"] = nlohmann::json::array();
    for (const auto& p : tf.points)
        j["points"].push_back({{"value", p.value},
                               {"colour", {p.colour.r, p.colour.g, p.colour.b}},
                               {"opacity", p.opacity}});
    return j;
}

TransferFunction transferFunctionFromJson(const nlohmann::json& j, const std::string& source,
                                          const std::string& defaultName) {
    TransferFunction tf;
    tf.name = defaultName;
    try {
        if (!j.is_object()) throw LoadError(source, "", "expected a JSON object");
        if (j.contains("version")) {
            const nlohmann::json& version = j["version"];
            if (!version.is_number_integer() || version.get<long long>() < 1)
                throw LoadError(source, "version", version.dump() + ", expected a whole number >= 1");
            if (version.get<long long>() > kTransferFunctionVersion)
                throw LoadError(source, "version",
                                version.dump() + " is newer than this SplatLab reads (" +
                                    std::to_string(kTransferFunctionVersion) + ")");
        }
        if (j.contains("name")) tf.name = j.at("name").get<std::string>();
        if (!j.contains("points") || !j["points"].is_array())
            throw LoadError(source, "points", "missing, expected an array of control points");
        for (const auto& p : j["points"]) {
            ControlPoint c;
            c.value = p.at("value").get<double>();
            const auto col = p.at("colour").get<std::vector<double>>();
            if (col.size() != 3) throw LoadError(source, "colour", "has " + std::to_string(col.size()) +
                                                                      " values, expected 3 (r, g, b)");
            c.colour = {col[0], col[1], col[2]};
            c.opacity = p.at("opacity").get<double>();
            tf.points.push_back(c);
        }
    } catch (const nlohmann::json::exception& e) {
        throw LoadError(source, "points", std::string("expected {value, colour[3], opacity}: ") + e.what());
    }
    if (auto err = validate(tf); !err.empty()) throw LoadError(source, "points", err);
    return tf;
}

TransferFunction loadTransferFunction(const std::filesystem::path& path) {
    const nlohmann::json j = readJsonFile(path, "a transfer function (.json)");
    return transferFunctionFromJson(j, path.string(), path.stem().string());
}

std::string transferFunctionText(const TransferFunction& tf) { return toJson(tf).dump(2) + "\n"; }

void saveTransferFunction(const TransferFunction& tf, const std::filesystem::path& path) {
    writeFileAtomically(path, transferFunctionText(tf));
}

TransferFunction transferFunctionFromSpec(const std::string& spec) {
    for (const auto& n : builtinPresetNames())
        if (spec == n) return builtinPreset(spec);
    if (spec.ends_with(".json") || std::filesystem::exists(spec)) return loadTransferFunction(spec);
    return builtinPreset(spec);   // throws, listing the known names
}

} // namespace renderer
