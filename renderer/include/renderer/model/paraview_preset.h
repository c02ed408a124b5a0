// ParaView's colour-map presets (the JSON its Color Map Editor imports and exports): a list of objects
// with "Name", "ColorSpace", "RGBPoints" [x, r, g, b, ...] and "Points" [x, opacity, midpoint,
// sharpness, ...], positions in data units. Read into a TransferFunction and written from one.
#pragma once
#include "renderer/model/transfer_function.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <string>

namespace renderer {

// The first preset of a ParaView preset list (or a single preset object). Only what a TransferFunction
// holds exactly is read: "ColorSpace" "RGB" (linear between the stops, as here), opacity points with
// midpoint 0.5 and sharpness 0 (linear). Without "Points", opacity ramps 0..1 over the colour stops'
// span (ParaView's default). Throws LoadError naming `source` and the field otherwise.
TransferFunction transferFunctionFromParaView(const nlohmann::json& j, const std::string& source);
TransferFunction loadParaViewPreset(const std::filesystem::path& path);
// A one-preset list ParaView imports: RGB colour space, linear opacity points. A TF in window fractions
// is written with its fractions as positions (ParaView then needs a rescale to the data).
nlohmann::json toParaView(const TransferFunction& tf);
std::string paraViewPresetText(const TransferFunction& tf);   // what saveParaViewPreset writes
void saveParaViewPreset(const TransferFunction& tf, const std::filesystem::path& path);   // atomic

} // namespace renderer
