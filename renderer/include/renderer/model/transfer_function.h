// Transfer function: control points over the normalised value domain [0,1] -> an RGBA lookup table.
// Opacity is extinction per unit length (EWA_NOTES): a point's `opacity` times SplatSettings::density
// is the extinction per voxel length. Presets are JSON files; the control points are what is saved.
#pragma once
#include "renderer/math/glm_config.h"

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace renderer {

struct ControlPoint {
    double value = 0.0;        // normalised data value in [0,1] (0 = range.lo, 1 = range.hi)
    glm::dvec3 colour{1.0};    // linear RGB in [0,1]
    double opacity = 0.0;      // in [0,1]; 0 makes voxels of this value invisible (never drawn)
    bool operator==(const ControlPoint&) const = default;
};

struct TransferFunction {
    std::string name;
    std::vector<ControlPoint> points;   // sorted by value; piecewise linear between them
    bool operator==(const TransferFunction&) const = default;
};

// Entries of the lookup table both the CPU oracle and the GL path index with a voxel's class.
constexpr int kLutSize = 4096;
using Lut = std::vector<glm::vec4>;     // kLutSize entries: rgb colour, a = opacity

// Colour (rgb) and opacity (a) at normalised `value`: linear between the points around it, the end
// points' own outside them (black and transparent with no points). bakeLut samples it per class.
glm::dvec4 evaluate(const TransferFunction& tf, double value);
Lut bakeLut(const TransferFunction& tf);
// Class of a value: which LUT entry it reads. Normalises over [lo, hi] and clamps; NaN gets class 0.
uint16_t classOf(float value, float lo, float hi);

// Presets by name: those in code ("ct-skin-bone", "ct-bone", "grey-ramp", "soft", "fire"), then each
// NAME.json of the bundled assets/presets ("bonsai"), sorted.
std::vector<std::string> builtinPresetNames();
// Throws RenderError listing the names if unknown, LoadError naming the file if a bundled one is bad.
TransferFunction builtinPreset(const std::string& name);
TransferFunction loadTransferFunction(const std::filesystem::path& path);   // throws LoadError
void saveTransferFunction(const TransferFunction& tf, const std::filesystem::path& path);  // atomic
std::string transferFunctionText(const TransferFunction& tf);   // what saveTransferFunction writes
// The JSON of a TF file, and back (sessions embed it): `source` names the file in errors, and
// `defaultName` is the name when the JSON gives none. Throws LoadError naming the field.
nlohmann::json toJson(const TransferFunction& tf);
TransferFunction transferFunctionFromJson(const nlohmann::json& j, const std::string& source,
                                          const std::string& defaultName);
// A preset name or a JSON file path, whichever `spec` is.
TransferFunction transferFunctionFromSpec(const std::string& spec);

} // namespace renderer
