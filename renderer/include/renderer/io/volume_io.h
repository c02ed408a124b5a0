// Readers for volume files: raw (flags or a name_WxHxD_type.raw name), NRRD (attached or detached
// header; raw, gzip or bzip2), MetaImage (.mhd/.mha, zlib), NIfTI-1 (.nii, .nii.gz), VolVis .slc,
// .dat (uint16 dims header) and image stacks (a folder, a numbered pattern, a multi-page TIFF) through
// OpenImageIO. Every failure throws LoadError naming the file, the field and what was expected;
// nothing returns a partial volume.
#pragma once
#include "renderer/model/volume.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace renderer {

enum class Endian { Little, Big };

struct RawOptions {
    glm::ivec3 dims{0};
    VoxelType type = VoxelType::U8;
    Endian endian = Endian::Little;
    glm::dvec3 spacing{1.0};
    size_t headerBytes = 0;           // bytes to skip before the voxels
};

// Reads dims and type from a file name such as "headsq_64x64x93_int16.raw" (".raw.gz" too);
// std::nullopt when the name does not follow that pattern.
std::optional<RawOptions> rawOptionsFromFileName(const std::filesystem::path& path);

// Every loader reports the fraction read to `progress` (streamed formats every 64 KiB, SLC every slice,
// image stacks every file; a multi-page TIFF, whose page count is unknown until read, not at all); when
// it returns false the loader throws Cancelled.
Volume loadRaw(const std::filesystem::path& path, const RawOptions& options, const ProgressCallback& progress = {});
Volume loadNrrd(const std::filesystem::path& path, const ProgressCallback& progress = {});
// MetaImage: .mha (data LOCAL) or .mhd with ElementDataFile; zlib-compressed data, ElementSpacing,
// Offset and TransformMatrix (kept as Volume::directions).
Volume loadMetaImage(const std::filesystem::path& path, const ProgressCallback& progress = {});
// NIfTI-1 single file (.nii, or gzip-compressed .nii.gz), either byte order; pixdim as spacing,
// scl_slope/scl_inter applied to the values, the sform (else qform) as origin and directions.
Volume loadNifti(const std::filesystem::path& path, const ProgressCallback& progress = {});
// VolVis SLC: 8-bit voxels, raw or run-length encoded slices.
Volume loadSlc(const std::filesystem::path& path, const ProgressCallback& progress = {});
// The .dat layout of the classic CT datasets: three little-endian uint16 dims, then uint16 voxels.
Volume loadDat(const std::filesystem::path& path, const ProgressCallback& progress = {});
// An image stack through OpenImageIO: a folder of slices (.tif, .tiff, .png; sorted by the number in
// their names), a printf pattern ("slice_%03d.png", numbered from the lowest that exists) or a
// multi-page TIFF. Slices must agree in size, channels (1) and pixel type (u8, u16, i16, f32).
Volume loadImageStack(const std::filesystem::path& pathOrPattern, const ProgressCallback& progress = {});

// Picks the reader from the path: a folder or a name with '%' is an image stack; otherwise by the
// extension (.nrrd, .nhdr, .mhd, .mha, .nii, .nii.gz, .slc, .dat, .tif, .tiff, .raw, .raw.gz); raw
// files need their dims in the file name unless `raw` is given. `progress` as the loaders above.
Volume loadVolume(const std::filesystem::path& path, const std::optional<RawOptions>& raw = std::nullopt,
                  const ProgressCallback& progress = {});
// loadVolume, then alignedToWorldAxes: the volume as the tools draw it, in its file's world frame. A
// LoadError from the alignment (axes too sheared to resample) names `path`.
Volume loadVolumeInWorldFrame(const std::filesystem::path& path, const std::optional<RawOptions>& raw = std::nullopt,
                              const ProgressCallback& progress = {});
// The extensions loadVolume() knows, for messages and file dialogs: ".nrrd, .nhdr, ...".
const char* supportedVolumeTypes();
// The same as a list for file browsers: the lower-case file extensions loadVolume() reads, with the dot.
const std::vector<std::string>& volumeFileExtensions();

// Bytes one volume's voxels may take in their type: SPLATLAB_MEMORY_BUDGET_MB when set, else half of
// what this process may use (physical memory, or a lower `ulimit -v` / `-d`). Every loader refuses a
// header that claims more before it allocates or decompresses anything.
uint64_t volumeMemoryBudget();
// Why `voxels` of `type` do not fit volumeMemoryBudget() ("need 600 MiB as uint8, more than the memory
// budget of 512 MiB (...)"), or std::nullopt where they fit.
std::optional<std::string> overMemoryBudget(uint64_t voxels, VoxelType type);

} // namespace renderer
