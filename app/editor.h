// The editor window: GLFW + a GL 4.5 core context, ImGui's GLFW and OpenGL3 backends, the ui panels
// and the splat renderer. The command line (main.cpp) parses flags into EditorOptions.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_settings.h"
#include "renderer/io/volume_io.h"
#include "renderer/model/window.h"
#include "ui/split_view.h"

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

struct EditorOptions {
    std::filesystem::path volumePath;     // empty: start with no volume (or the session's)
    std::filesystem::path sessionPath;    // non-empty: open this session (after the flags, replacing them)
    std::string tfSpec = "ct-skin-bone";  // preset name or TF JSON file
    std::string sceneName;                // --scene: a demo scene (volumePath is then "scene:NAME")
    bool sceneLook = true, sceneCamera = true; // its own look and view, unless --tf, --density, --shading
                                             // or --camera (--fit) said
    renderer::Camera camera;              // the starting view (its `up` is replaced by upAxis)
    bool fit = false;                     // start framed (--fit): as Settings > Camera > Frame
    std::string upAxis = "z";             // object axis shown upwards: x, y, z, -x, -y, -z (headsq: -z)
    std::filesystem::path screenshotPath; // non-empty: write a PNG of the window after `frames` frames
    std::filesystem::path saveImagePath;  // non-empty: after `frames` frames, save the view (Save image)
    int frames = 0;                       // > 0: exit after this many frames (0: until the window closes)
    int width = 1280, height = 800;       // window size in screen coordinates
    renderer::SplatSettings settings;     // the starting settings, heatmap included (the command line's)
    bool cullingByDriver = false;         // no culling flag: occlusion culling as the driver's profile says
    double heatmapOpacity = 1.0;          // the heatmap over the image: 0 the image only, 1 the heatmap only
    // --split A,B[,C,D]: the viewport split in two or four panes with these filters (all in
    // settings.compositing); --split-difference adds the |A - B| pane, --split-difference truth the
    // |A - ground truth| one (ui/split_view.h).
    std::vector<renderer::FilterMode> split;
    ui::SplitDifference splitDifference = ui::SplitDifference::Off;
    renderer::WindowSettings window;      // the starting window (--window)
    std::optional<renderer::RawOptions> raw;   // how to read the volume argument if it is headerless raw
    std::vector<std::string> tabs;        // panels brought to the front of their regions (--tab)
    bool continuous = false;              // render every frame (Performance panel)
    double spinDegPerS = 0.0;             // and turn the camera this fast (implies continuous)
    bool preview = false;                 // show the preview level alone (--preview)
    std::filesystem::path sessionOutPath; // non-empty: the session is written here when the editor closes
    int measureEdits = 0;                 // > 0: --measure-interactive (interactive_probe.h)
};

// Runs the editor until the window closes, or for `frames` frames. Returns the process exit code:
// 0, or 1 after printing one line to stderr (no window, or any error while running scripted frames).
// SIGINT and SIGTERM close the window as its close button does.
// The first frame measures the viewport and the second renders it, so a screenshot needs frames >= 2.
int runEditor(const EditorOptions& options);
