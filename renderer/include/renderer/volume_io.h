// Readers for volume files: raw (flags or a name_WxHxD_type.raw name) and NRRD (attached or detached
// header, raw or gzip encoding). Every failure throws LoadError naming the file, the field and what
// was expected; nothing returns a partial volume.
#pragma once
#include "renderer/volume.h"

#include <filesystem>
#include <optional>

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

Volume loadRaw(const std::filesystem::path& path, const RawOptions& options);
Volume loadNrrd(const std::filesystem::path& path);
// Picks the reader from the extension (.nrrd, .nhdr, .raw, .raw.gz); raw files need their dims in
// the file name unless `raw` is given.
Volume loadVolume(const std::filesystem::path& path, const std::optional<RawOptions>& raw = std::nullopt);

// Largest volume the loaders accept, in voxels: guards products of lying header fields.
constexpr size_t kMaxVoxels = size_t(1) << 31;

} // namespace renderer
