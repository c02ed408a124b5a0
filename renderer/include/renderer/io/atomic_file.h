// Saving user files (TF files, sessions, images) so that a crash, a full disk or a bad path never costs
// the user the file they had.
#pragma once
#include <filesystem>
#include <functional>
#include <string>

namespace renderer {

// Calls write(tmp) to fill a temporary file beside `path`, then renames it over `path`: readers see the
// old file or the new one, never half of one. `write` throws on failure; a LoadError naming `path`
// passes on, and no temporary file is left behind either way.
void replaceFileAtomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& tmp)>& write);

// replaceFileAtomically with `text` as the file's bytes.
void writeFileAtomically(const std::filesystem::path& path, const std::string& text);

} // namespace renderer
