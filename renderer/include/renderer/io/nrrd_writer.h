// Writing a Volume as NRRD, the one volume format SplatLab writes (generated test data: the phantom).
// loadNrrd reads back what this writes: dims, type, spacing, origin, axes and values.
#pragma once
#include "renderer/model/volume.h"

#include <filesystem>
#include <vector>

namespace renderer {

struct NrrdWriteOptions {
    bool gzip = false; // "encoding: gzip" (zlib level 1: noisy data barely shrinks, so spend little time)
};

// Writes `volume` in its own VoxelType, little-endian. A path ending in .nhdr gets a detached header and
// its data beside it (NAME.raw, or NAME.raw.gz with gzip), written first; any other name (.nrrd) one
// file. Each file is replaced atomically (atomic_file.h). Throws RenderError, before writing anything,
// where a value is not finite or is not a whole number within an integer type's range (no silent
// clamping); LoadError naming the file when it cannot be written. Returns the files written, header first.
std::vector<std::filesystem::path> saveNrrd(const Volume& volume, const std::filesystem::path& path,
                                            const NrrdWriteOptions& options = {});

} // namespace renderer
