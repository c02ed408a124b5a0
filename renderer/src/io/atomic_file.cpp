// replaceFileAtomically, writeFileAtomically, checkFileReplaceable (atomic_file.h).
#include "renderer/io/atomic_file.h"

#include "renderer/errors.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <random>
#include <system_error>

namespace renderer {

namespace fs = std::filesystem;

namespace {

// Temporary files are named ".NAME.splatlab-XXXXXXXX.tmp" in the target's folder: unique per save, so a
// save killed half-way leaves a file that blocks nothing, and recognisable, so a later save can remove it.
constexpr const char* kTempTag = ".splatlab-";
// A temporary file of ours this old is left from a killed save: a live one exists only while a save
// writes its bytes (seconds).
constexpr auto kStaleAfter = std::chrono::hours(1);

// The file a save replaces: `path`, or where its chain of symlinks ends (relative links resolve against
// their own folder). A loop of links fails as the kernel's ELOOP would.
fs::path finalTarget(const fs::path& path) {
    fs::path at = path;
    std::error_code ec;
    for (int hops = 0; fs::is_symlink(fs::symlink_status(at, ec)); ++hops) {
        if (hops == 40) throw LoadError(path.string(), "", "cannot write: too many levels of symbolic links");
        const fs::path link = fs::read_symlink(at, ec);
        if (ec) throw LoadError(path.string(), "", "cannot follow the symbolic link: " + ec.message());
        at = link.is_absolute() ? link : at.parent_path() / link;
    }
    return at;
}

void requireReplaceableKind(const fs::path& path, const fs::path& target) {
    std::error_code ec;
    const fs::file_status st = fs::status(target, ec);
    if (!fs::exists(st) || fs::is_regular_file(st)) return;
    const std::string kind = fs::is_directory(st)   ? "a folder"
                             : fs::is_fifo(st)      ? "a FIFO"
                             : fs::is_socket(st)    ? "a socket"
                             : fs::is_character_file(st) || fs::is_block_file(st) ? "a device"
                                                                                    : "not a regular file";
    const std::string via = target == path ? "" : " (through a symbolic link to '" + target.string() + "')";
    throw LoadError(path.string(), "", "cannot write: it is " + kind + via +
                                           "; SplatLab saves only to regular files (name a file to create or replace)");
}

fs::path folderOf(const fs::path& target) { return target.parent_path().empty() ? fs::path(".") : target.parent_path(); }

// Removes temporary files of ours for `target` that a killed save left behind.
void removeStaleTemps(const fs::path& target) {
    std::error_code ec;
    const std::string prefix = "." + target.filename().string() + kTempTag;
    const auto now = fs::file_time_type::clock::now();
    for (const auto& entry : fs::directory_iterator(folderOf(target), ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(prefix, 0) != 0 || name.size() < 4 || name.compare(name.size() - 4, 4, ".tmp") != 0) continue;
        std::error_code entryEc;
        if (!entry.is_regular_file(entryEc)) continue;
        const auto written = entry.last_write_time(entryEc);
        if (!entryEc && now - written > kStaleAfter) fs::remove(entry.path(), entryEc);
    }
}

// Creates a new, empty temporary file beside `target` (never an existing one: O_EXCL) and returns its name.
fs::path createTemp(const fs::path& path, const fs::path& target) {
    std::random_device seed;
    std::mt19937_64 random(seed());
    const fs::path folder = folderOf(target);
    for (int attempt = 0; attempt < 100; ++attempt) {
        char tag[17];
        std::snprintf(tag, sizeof tag, "%016llx", static_cast<unsigned long long>(random()));
        const fs::path tmp = folder / ("." + target.filename().string() + kTempTag + std::string(tag, 8) + ".tmp");
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            return tmp;
        }
        if (errno != EEXIST) {
            std::error_code ec;
            const std::string reason = !fs::is_directory(folder, ec)
                                           ? "the folder '" + folder.string() + "' does not exist"
                                           : std::string(std::strerror(errno)) + " (in '" + folder.string() + "')";
            throw LoadError(path.string(), "", "cannot write: " + reason);
        }
    }
    throw LoadError(path.string(), "", "cannot write: no free temporary name in '" + folder.string() + "'");
}

} // namespace

void requireRegularFile(const fs::path& path, const std::string& what) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st) || fs::is_regular_file(st)) return;
    throw LoadError(path.string(), "", std::string(fs::is_directory(st) ? "is a folder" : "is not a regular file") +
                                           ", expected " + what);
}

void checkFileReplaceable(const fs::path& path) {
    const fs::path target = finalTarget(path);
    requireReplaceableKind(path, target);
    const fs::path probe = createTemp(path, target);
    std::error_code ec;
    fs::remove(probe, ec);
}

void replaceFileAtomically(const fs::path& path, const std::function<void(const fs::path& tmp)>& write) {
    const fs::path target = finalTarget(path);
    requireReplaceableKind(path, target);
    removeStaleTemps(target);
    const fs::path tmp = createTemp(path, target);
    std::error_code ec;
    try {
        write(tmp);
    } catch (...) {
        fs::remove(tmp, ec);
        throw;
    }
    // Checked again: the target may have changed kind while the file was written.
    try {
        requireReplaceableKind(path, target);
    } catch (...) {
        fs::remove(tmp, ec);
        throw;
    }
    fs::rename(tmp, target, ec);
    if (ec) {
        const std::string reason = "cannot replace: " + ec.message();
        fs::remove(tmp, ec);
        throw LoadError(path.string(), "", reason);
    }
}

void writeFileAtomically(const fs::path& path, const std::string& text) {
    replaceFileAtomically(path, [&](const fs::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.close();
        if (!out) throw LoadError(path.string(), "", "cannot write (" + tmp.string() + ")");
    });
}

} // namespace renderer
