// Saving user files (TF files, sessions) so that a crash, a full disk or a bad path never costs the
// user the file they had.
#pragma once
#include <filesystem>
#include <string>

namespace renderer {

// Writes `text` to a temporary file beside `path`, then renames it over `path`: readers see the old
// file or the new one, never half of one. Throws LoadError naming `path`; a failure leaves no
// temporary file behind.
void writeFileAtomically(const std::filesystem::path& path, const std::string& text);

} // namespace renderer
