// Reading the JSON files users give (TF presets, sessions): every failure a LoadError naming the file.
#pragma once
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace renderer {

// Parses `path`; `what` names what the file should hold, for the error a folder gets.
nlohmann::json readJsonFile(const std::filesystem::path& path, const std::string& what);

} // namespace renderer
