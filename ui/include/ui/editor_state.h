// What the editor's panels edit: plain data, no GL and no ImGui. The app owns one and hands it to the
// panels each frame; the renderer reads the camera and settings from it.
#pragma once
#include "renderer/camera.h"
#include "renderer/splat_settings.h"
#include "renderer/window.h"

#include <array>
#include <string>

namespace ui {

struct EditorState {
    renderer::Camera camera; // orbit camera; "Reset camera" restores renderer::Camera{}, keeping `up`
    renderer::SplatSettings settings;        // what every render of the viewport uses
    std::string presetName = "ct-skin-bone"; // built-in TF preset, or the file name of a TF loaded from disk
    std::array<float, 3> background{0.055f, 0.060f, 0.075f}; // linear RGB behind the volume
    std::string errorMessage; // shown in a modal until dismissed; empty when none
    renderer::WindowSettings window; // which data values map onto the TF (custom: data units)
    bool histogramLog = true;        // the Window section's histogram: log-scale counts
    bool gradientsReady = false;     // the scene has gradients: shading and surface splats can be on
    bool showHeatmap = false;        // the viewport shows the filter-mode heatmap instead of the image
};

} // namespace ui
