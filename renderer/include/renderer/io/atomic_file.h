// Saving user files (TF files, sessions, images) so that a crash, a full disk or a bad path never costs
// the user the file they had, and a save never replaces something that is not a regular file.
#pragma once
#include <filesystem>
#include <functional>
#include <string>

namespace renderer {

// Calls write(tmp) to fill a temporary file beside the file `path` names, then renames it over that file:
// readers see the old file or the new one, never half of one. A symlink is written through: its final
// target is replaced and the link stays. `write` throws on failure; a LoadError naming `path` passes on,
// and no temporary file is left behind either way. Refuses (LoadError) a target that exists and is not a
// regular file (a folder, device, FIFO or socket): SplatLab never replaces those.
void replaceFileAtomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& tmp)>& write);

// replaceFileAtomically with `text` as the file's bytes.
void writeFileAtomically(const std::filesystem::path& path, const std::string& text);

// What replaceFileAtomically would fail on before it calls `write`, checked up front so that a long
// render does not end in a refused save: the target's kind, its folder, and that a file can be created
// there. Throws the same LoadError replaceFileAtomically would.
void checkFileReplaceable(const std::filesystem::path& path);

// Throws a LoadError naming `path` when it exists and is not a regular file (a FIFO would block a reader
// forever, a device would be read without end). `what` names what the file should hold.
void requireRegularFile(const std::filesystem::path& path, const std::string& what);

} // namespace renderer
