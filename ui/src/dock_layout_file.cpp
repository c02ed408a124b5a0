// The dock layout kept between runs (dock_layout.h): split ratios by node name and the panels'
// placements, as JSON in the config folder. What the file holds is checked before any of it is applied.
#include "renderer/errors.h"
#include "renderer/io/atomic_file.h"
#include "renderer/io/json_file.h"
#include "ui/dock_layout.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace ui {

namespace {
const char* const kLayoutFile = "layout.json";
}

void saveDockLayout(const DockLayout& layout, const std::filesystem::path& folder) {
    nlohmann::json ratios = nlohmann::json::object(), panels = nlohmann::json::object();
    for (const DockNode& node : layout.nodes)
        if (!node.isLeaf()) ratios[node.name] = node.ratio;
    for (const auto& [title, place] : layout.panels)
        panels[title] = {{"region", place.region}, {"open", place.open}};
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec)
        throw renderer::LoadError(folder.string(), "",
                                  "cannot create the settings folder (" + ec.message() + ")");
    renderer::writeFileAtomically(folder / kLayoutFile,
                                  nlohmann::json{{"ratios", ratios}, {"panels", panels}}.dump(2) + "\n");
}

void loadDockLayout(DockLayout& layout, const std::filesystem::path& folder) {
    const std::filesystem::path file = folder / kLayoutFile;
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) return;
    const nlohmann::json root = renderer::readJsonFile(file, "an editor layout");
    auto fail = [&](const std::string& field, const std::string& expected) {
        throw renderer::LoadError(file.string(), field, expected);
    };
    if (!root.is_object()) fail("", "expected a JSON object");
    DockLayout read = layout; // applied only once the whole file passed
    if (root.contains("ratios")) {
        if (!root["ratios"].is_object()) fail("ratios", "expected an object of split names and ratios");
        for (const auto& [name, ratio] : root["ratios"].items()) {
            if (!ratio.is_number() || !(ratio.get<double>() > 0.0 && ratio.get<double>() < 1.0))
                fail("ratios." + name, "expected a number between 0 and 1");
            const int node = read.find(name);
            if (node >= 0 && !read.nodes[size_t(node)].isLeaf())
                read.nodes[size_t(node)].ratio = ratio.get<float>();
        }
    }
    if (root.contains("panels")) {
        if (!root["panels"].is_object()) fail("panels", "expected an object of panel titles");
        for (const auto& [title, place] : root["panels"].items()) {
            if (!place.is_object() || !place.contains("region") || !place["region"].is_string() ||
                !place.contains("open") || !place["open"].is_boolean())
                fail("panels." + title, "expected {\"region\": a dock name, \"open\": true or false}");
            read.panels[title] = {place["region"].get<std::string>(), place["open"].get<bool>()};
        }
    }
    layout = std::move(read);
}

} // namespace ui
