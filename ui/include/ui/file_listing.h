// What the in-app file browser lists and remembers, with no ImGui: the formats each path field can
// open, a folder's entries filtered to them, and the recent files of each kind kept between runs in
// the user's config folder. The browser's window is file_browser.h.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ui {

// What a path field holds; each kind lists its own formats and keeps its own recent files.
enum class FileKind { Volume, TransferFunction, Session, Image };
constexpr int kFileKinds = 4;
const char* fileKindName(FileKind kind); // "volume", "transfer function", ... (also the recent file's keys)

// The extensions (lower case, with the dot) a field of `kind` opens or writes: volumes what
// renderer::loadVolume reads, TFs and sessions .json, images what Save image writes.
const std::vector<std::string>& fileKindExtensions(FileKind kind);
// Whether `name` ends with one of `kind`'s extensions, in any case ("HEAD.NII.GZ" is a volume).
bool matchesFileKind(const std::string& name, FileKind kind);

struct FolderEntry {
    std::string name; // the entry's file name, no folder
    bool folder = false;
    std::uintmax_t bytes = 0; // files only
};

struct FolderListing {
    std::filesystem::path folder; // absolute, normalised
    std::vector<FolderEntry>
        entries;            // folders first, then the files of the kind; each by name, ignoring case
    std::string error;      // why the folder could not be read ("" when it could), naming it
    size_t hiddenFiles = 0; // files of other formats left out
};

// Lists `folder` for a field of `kind`: its sub-folders and the files `kind` opens. Names starting with
// a dot are left out. A folder that cannot be read gives an empty listing and an error naming it.
FolderListing listFolder(const std::filesystem::path& folder, FileKind kind);

// The most recently used paths of each kind, newest first, at most kMaxRecent each.
struct RecentFiles {
    static constexpr size_t kMaxRecent = 10;
    std::array<std::vector<std::string>, kFileKinds> paths;
    std::vector<std::string>& of(FileKind kind) { return paths[size_t(kind)]; }
    const std::vector<std::string>& of(FileKind kind) const { return paths[size_t(kind)]; }
};

// Puts `path` (made absolute) first in `kind`'s list, removing an earlier entry of it and the oldest
// past kMaxRecent.
void addRecentFile(RecentFiles& recent, FileKind kind, const std::filesystem::path& path);

// The folder SplatLab keeps its settings in: $SPLATLAB_CONFIG_DIR when set (tests point it at a temp
// folder), else $XDG_CONFIG_HOME/splatlab, else ~/.config/splatlab; empty when none of these is set.
std::filesystem::path configFolder();

// The recent files in `folder` (recent_files.json). A missing file gives empty lists; a file that is not
// what SplatLab writes throws LoadError naming it and the field.
RecentFiles loadRecentFiles(const std::filesystem::path& folder);
// Writes them there atomically, creating the folder. Throws LoadError naming the file.
void saveRecentFiles(const RecentFiles& recent, const std::filesystem::path& folder);

} // namespace ui
