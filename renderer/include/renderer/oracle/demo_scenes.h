// Demo scenes: the hard cases (hard_cases.h) at a size for the editor, and 000 fig. 8's 512x512x3 board,
// each with a line on what to look for. They open by name: `editor --scene NAME`, the Settings panel's
// "Demo scene", and "scene:NAME" wherever a volume path goes (sessions keep it so).
#pragma once
#include "renderer/io/volume_io.h"
#include "renderer/math/camera.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/volume.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace renderer {

struct DemoSceneInfo {
    std::string name;    // file-name safe, as --scene takes it
    std::string lookFor; // one line for a class: what this scene shows
};

// Every demo scene, in menu order: the hard cases', then "board-512".
const std::vector<DemoSceneInfo>& demoSceneList();
bool isDemoScene(const std::string& name);
std::string demoSceneNames(); // "near-plane, far-away, ...": for messages

struct DemoScene {
    DemoSceneInfo info;
    Volume volume;
    TransferFunction tf;
    Camera camera; // for a viewport `heightPx` tall: the board's view is panned in pixels
};

// The scene called `name`; its camera framed for an image `heightPx` pixels tall. Throws LoadError
// naming the scenes there are.
DemoScene demoScene(const std::string& name, int heightPx);

// "scene:NAME" as a volume path: NAME, when no file of that name exists; else nothing.
std::optional<std::string> demoSceneOfPath(const std::filesystem::path& path);
std::filesystem::path demoScenePath(const std::string& name); // "scene:NAME"

// A volume path as every tool reads it: a demo scene's volume (demoSceneOfPath), or the file in its
// world frame (loadVolumeInWorldFrame).
Volume loadVolumeOrScene(const std::filesystem::path& path, const std::optional<RawOptions>& raw = std::nullopt,
                         const ProgressCallback& progress = {});

} // namespace renderer
