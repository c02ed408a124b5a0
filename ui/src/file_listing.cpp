// Folder listings, format filters and the recent-files file (file_listing.h); no ImGui here.
#include "ui/file_listing.h"

#include "renderer/errors.h"
#include "renderer/io/atomic_file.h"
#include "renderer/io/json_file.h"
#include "renderer/io/volume_io.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace ui {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string text) {
    for (char& c : text)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

const char* const kRecentFile = "recent_files.json";

} // namespace

const char* fileKindName(FileKind kind) {
    switch (kind) {
    case FileKind::Volume:
        return "volume";
    case FileKind::TransferFunction:
        return "transfer function";
    case FileKind::Session:
        return "session";
    case FileKind::Image:
        return "image";
    }
    return "file";
}

const std::vector<std::string>& fileKindExtensions(FileKind kind) {
    static const std::vector<std::string> json{".json"};
    static const std::vector<std::string> tfs{".json", ".xml"}; // ours and ParaView's; Slicer's presets.xml
    static const std::vector<std::string> images{".png", ".exr", ".tif", ".tiff"}; // Save image's formats
    switch (kind) {
    case FileKind::Volume:
        return renderer::volumeFileExtensions();
    case FileKind::TransferFunction:
        return tfs;
    case FileKind::Session:
        return json;
    case FileKind::Image:
        return images;
    }
    return json;
}

bool matchesFileKind(const std::string& name, FileKind kind) {
    const std::string lowered = lower(name);
    return std::ranges::any_of(fileKindExtensions(kind),
                               [&](const std::string& ext) { return lowered.ends_with(ext); });
}

FolderListing listFolder(const fs::path& folder, FileKind kind) {
    FolderListing listing;
    std::error_code ec;
    listing.folder = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    if (ec) listing.folder = folder.lexically_normal();
    fs::directory_iterator it(listing.folder, fs::directory_options::skip_permission_denied, ec);
    if (ec) {
        listing.error = listing.folder.string() + ": cannot list the folder (" + ec.message() + ")";
        return listing;
    }
    for (; it != fs::directory_iterator(); it.increment(ec)) {
        if (ec) {
            listing.error = listing.folder.string() + ": listing stopped (" + ec.message() + ")";
            break;
        }
        const std::string name = it->path().filename().string();
        if (name.starts_with(".")) continue;
        std::error_code kindError;
        if (it->is_directory(kindError)) {
            listing.entries.push_back({name, true, 0});
        } else if (matchesFileKind(name, kind)) {
            const std::uintmax_t bytes = it->file_size(kindError);
            listing.entries.push_back({name, false, kindError ? 0 : bytes});
        } else {
            ++listing.hiddenFiles;
        }
    }
    std::ranges::sort(listing.entries, [](const FolderEntry& a, const FolderEntry& b) {
        if (a.folder != b.folder) return a.folder;
        const std::string la = lower(a.name), lb = lower(b.name);
        return la != lb ? la < lb : a.name < b.name;
    });
    return listing;
}

void addRecentFile(RecentFiles& recent, FileKind kind, const fs::path& path) {
    std::error_code ec;
    fs::path absolute = fs::absolute(path, ec);
    const std::string entry = (ec ? path : absolute).lexically_normal().string();
    std::vector<std::string>& list = recent.of(kind);
    std::erase(list, entry);
    list.insert(list.begin(), entry);
    if (list.size() > RecentFiles::kMaxRecent) list.resize(RecentFiles::kMaxRecent);
}

fs::path configFolder() {
    if (const char* dir = std::getenv("SPLATLAB_CONFIG_DIR"); dir && *dir) return dir;
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg) return fs::path(xdg) / "splatlab";
    if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".config" / "splatlab";
    return {};
}

RecentFiles loadRecentFiles(const fs::path& folder) {
    RecentFiles recent;
    const fs::path file = folder / kRecentFile;
    std::error_code ec;
    if (!fs::exists(file, ec)) return recent;
    const nlohmann::json root = renderer::readJsonFile(file, "a recent-files list");
    if (!root.is_object()) throw renderer::LoadError(file.string(), "", "expected a JSON object");
    for (int k = 0; k < kFileKinds; ++k) {
        const char* key = fileKindName(FileKind(k));
        if (!root.contains(key)) continue;
        const nlohmann::json& list = root[key];
        if (!list.is_array()) throw renderer::LoadError(file.string(), key, "expected an array of paths");
        for (const nlohmann::json& path : list) {
            if (!path.is_string())
                throw renderer::LoadError(file.string(), key, "expected an array of paths");
            if (recent.paths[size_t(k)].size() < RecentFiles::kMaxRecent)
                recent.paths[size_t(k)].push_back(path.get<std::string>());
        }
    }
    return recent;
}

void saveRecentFiles(const RecentFiles& recent, const fs::path& folder) {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec)
        throw renderer::LoadError(folder.string(), "",
                                  "cannot create the settings folder (" + ec.message() + ")");
    nlohmann::json root = nlohmann::json::object();
    for (int k = 0; k < kFileKinds; ++k)
        root[fileKindName(FileKind(k))] = recent.paths[size_t(k)];
    renderer::writeFileAtomically(folder / kRecentFile, root.dump(2) + "\n");
}

} // namespace ui
