// The editor window: GLFW + a GL 4.5 core context, ImGui's GLFW and OpenGL3 backends, the ui panels
// and the splat renderer. The command line (main.cpp) parses flags into EditorOptions.
#pragma once
#include <filesystem>
#include <string>

struct EditorOptions {
    std::filesystem::path volumePath;        // empty: start with no volume
    std::string tfSpec = "ct-skin-bone";     // preset name or TF JSON file
    std::filesystem::path screenshotPath;    // non-empty: write a PNG of the window after `frames` frames
    int frames = 0;                          // > 0: exit after this many frames (0: until the window closes)
    int width = 1280, height = 800;          // window size in screen coordinates
};

// Runs the editor until the window closes, or for `frames` frames. Returns the process exit code:
// 0, or 1 after printing one line to stderr (no window, or any error while running scripted frames).
int runEditor(const EditorOptions& options);
