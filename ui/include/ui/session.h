// Sessions: what the editor shows, saved to a JSON file and opened again. A session holds the
// volume's path, the transfer function, the window, the camera, every splatting setting, the view
// toggles and the 3D-mouse mapping; it is written atomically (a failed save keeps the old file).
#pragma once
#include "ui/editor_state.h"

#include <filesystem>

namespace ui {

// The session format's version, written as "splatlab_session".
constexpr int kSessionVersion = 1;

// Saves `state` and `volume` to `file`. The volume's path is stored relative to the session's folder
// when it can be (a session and its data then move together). Throws LoadError naming `file`.
void saveSession(const EditorState& state, const std::filesystem::path& volume, const std::filesystem::path& file);

// Opens `file` into `state` and returns the volume's path (empty: the session names none). Sections
// or fields the file leaves out keep what `state` has. Throws LoadError naming the file, the field
// ("camera.distance") and what was expected; `state` is then unchanged.
std::filesystem::path loadSession(const std::filesystem::path& file, EditorState& state);

} // namespace ui
