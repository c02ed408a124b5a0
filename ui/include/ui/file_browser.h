// Path fields with an in-app file browser: a Browse button beside the field opens a popup on the
// field's folder listing its sub-folders and the files that field can open (file_listing.h), with the
// kind's recent files above. Plain data here; the popup is drawn in file_browser.cpp.
#pragma once
#include "ui/file_listing.h"

#include <filesystem>
#include <string>

namespace ui {

struct EditorState;

// The open browser (one at a time): what it lists and the file name picked so far.
struct FileBrowserState {
    FileKind kind = FileKind::Volume;
    FolderListing listing; // listing.folder is the folder shown
    std::string name;      // the file picked or typed, in listing.folder
    bool stale = true;     // list the folder again next frame
};

// Draws `label`'s text field (with `tooltip`) and a Browse button beside it; the button opens the browser
// on the field's folder. Returns true on the frame a path was chosen in the browser (`path` then holds it).
bool pathField(const char* label, std::string& path, FileKind kind, EditorState& state, const char* tooltip);

// Records `path` as just opened or saved: first in its kind's recent list, which is written to
// state.configDir (when set) at once, so a crash later keeps it. A failed write is printed to stderr
// once: the list still works for this run.
void noteRecentFile(EditorState& state, FileKind kind, const std::filesystem::path& path);

} // namespace ui
