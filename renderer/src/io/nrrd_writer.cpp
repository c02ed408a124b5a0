// saveNrrd (nrrd_writer.h): the header text, then the voxels a slice at a time, raw or through zlib's
// gzip stream, so a 512^3 volume never needs a second full-size buffer.
#include "renderer/io/nrrd_writer.h"

#include "renderer/errors.h"
#include "renderer/io/atomic_file.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

namespace renderer {
namespace {

namespace fs = std::filesystem;

// Names loadNrrd reads (and teem writes).
const char* nrrdTypeName(VoxelType type) {
    switch (type) {
    case VoxelType::U8:
        return "uint8";
    case VoxelType::U16:
        return "uint16";
    case VoxelType::I16:
        return "int16";
    case VoxelType::F32:
        return "float";
    }
    return "float";
}

template <class T> bool fitsInteger(float v) {
    return std::isfinite(v) && v == std::round(v) && v >= float(std::numeric_limits<T>::min()) &&
           v <= float(std::numeric_limits<T>::max());
}

bool fitsType(float v, VoxelType type) {
    switch (type) {
    case VoxelType::U8:
        return fitsInteger<uint8_t>(v);
    case VoxelType::U16:
        return fitsInteger<uint16_t>(v);
    case VoxelType::I16:
        return fitsInteger<int16_t>(v);
    case VoxelType::F32:
        return true; // NaN and infinities are floats too
    }
    return true;
}

// Refuses a value the file's type cannot hold, naming the first such voxel.
void checkValuesFitTheType(const Volume& volume) {
    if (volume.values.type() == volume.type) return;   // held in the file's type: every value fits it
    size_t i = 0;
    while (i < volume.values.size() && fitsType(volume.values[i], volume.type)) ++i;
    if (i == volume.values.size()) return;
    const float bad = volume.values[i];
    const size_t dx = size_t(volume.dims.x), dy = size_t(volume.dims.y);
    char text[160];
    std::snprintf(text, sizeof text, "voxel (%zu, %zu, %zu) is %g: not a whole number within %s", i % dx,
                  i / dx % dy, i / (dx * dy), double(bad), voxelTypeName(volume.type));
    throw RenderError(volume.name + ": cannot write as " + voxelTypeName(volume.type) + ", " + text);
}

std::string vectorText(const glm::dvec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.17g,%.17g,%.17g)", v.x, v.y, v.z);
    return text;
}

// The header; `dataFile` empty for an attached one (the voxels follow its blank line).
std::string headerText(const Volume& volume, bool gzip, const std::string& dataFile) {
    std::string h = "NRRD0004\n# written by SplatLab: " + volume.name + "\n";
    h += std::string("type: ") + nrrdTypeName(volume.type) + "\ndimension: 3\nspace: 3D-right-handed\n";
    h += "sizes: " + std::to_string(volume.dims.x) + " " + std::to_string(volume.dims.y) + " " +
         std::to_string(volume.dims.z) + "\n";
    // Each axis's step in the world: its unit direction times its spacing.
    h += "space directions: " + vectorText(volume.directions[0] * volume.spacing.x) + " " +
         vectorText(volume.directions[1] * volume.spacing.y) + " " +
         vectorText(volume.directions[2] * volume.spacing.z) + "\n";
    h += "space origin: " + vectorText(volume.origin) + "\n";
    h += std::string("endian: little\nencoding: ") + (gzip ? "gzip" : "raw") + "\n";
    if (!dataFile.empty()) h += "data file: " + dataFile + "\n";
    return h + "\n";
}

// One slice's values as the file's type, little-endian.
void appendSliceBytes(const Volume& volume, int z, std::string& bytes) {
    const size_t count = size_t(volume.dims.x) * size_t(volume.dims.y), first = volume.index(0, 0, z);
    const size_t size = voxelTypeBytes(volume.type);
    bytes.resize(count * size);
    const auto put = [&](auto value, size_t i) {
        std::memcpy(&bytes[i * size], &value, size);
        if constexpr (std::endian::native == std::endian::big)
            std::reverse(bytes.begin() + std::ptrdiff_t(i * size),
                         bytes.begin() + std::ptrdiff_t((i + 1) * size));
    };
    for (size_t i = 0; i < count; ++i) {
        const float v = volume.values[first + i];
        switch (volume.type) {
        case VoxelType::U8:
            put(uint8_t(v), i);
            break;
        case VoxelType::U16:
            put(uint16_t(v), i);
            break;
        case VoxelType::I16:
            put(int16_t(v), i);
            break;
        case VoxelType::F32:
            put(v, i);
            break;
        }
    }
}

// Writes `header` then every slice to `file`, gzip-compressed when asked; `path` names it in errors.
void writeFile(const fs::path& file, const fs::path& path, const std::string& header, const Volume* voxels,
               bool gzip) {
    std::ofstream out(file, std::ios::binary);
    out << header;
    const auto fail = [&](const std::string& why) {
        throw LoadError(path.string(), "", "cannot write: " + why);
    };
    if (voxels) {
        z_stream zs{};
        // windowBits 15 + 16: a gzip stream (the NRRD "gzip" encoding); level 1 for speed.
        if (gzip && deflateInit2(&zs, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
            fail("zlib: out of memory");
        std::string slice, packed(size_t(1) << 18, '\0');
        for (int z = 0; z < voxels->dims.z && out; ++z) {
            appendSliceBytes(*voxels, z, slice);
            if (!gzip) {
                out.write(slice.data(), std::streamsize(slice.size()));
                continue;
            }
            zs.next_in = reinterpret_cast<Bytef*>(slice.data());
            zs.avail_in = uInt(slice.size());
            const int flush = z + 1 == voxels->dims.z ? Z_FINISH : Z_NO_FLUSH;
            do {
                zs.next_out = reinterpret_cast<Bytef*>(packed.data());
                zs.avail_out = uInt(packed.size());
                deflate(&zs, flush);
                out.write(packed.data(), std::streamsize(packed.size() - zs.avail_out));
            } while (zs.avail_out == 0);
        }
        if (gzip) deflateEnd(&zs);
    }
    out.close();
    if (!out) fail("the write failed (disk full?)");
}

} // namespace

std::vector<fs::path> saveNrrd(const Volume& volume, const fs::path& path, const NrrdWriteOptions& options) {
    // 1. Everything refusable before a byte is written.
    if (volume.voxelCount() == 0) throw RenderError(volume.name + ": has no voxels to write");
    if (volume.values.size() != volume.voxelCount())
        throw RenderError(volume.name + ": has " + std::to_string(volume.values.size()) + " values for " +
                          std::to_string(volume.voxelCount()) + " voxels");
    checkValuesFitTheType(volume);
    const bool detached = path.extension() == ".nhdr";
    const fs::path dataPath =
        detached ? fs::path(path).replace_extension(options.gzip ? ".raw.gz" : ".raw") : fs::path();
    if (detached) {
        checkFileReplaceable(dataPath);
        checkFileReplaceable(path);
    }

    // 2. Detached: the data, then the header naming it, so a header never names a half-written file.
    if (!detached) {
        replaceFileAtomically(path, [&](const fs::path& tmp) {
            writeFile(tmp, path, headerText(volume, options.gzip, ""), &volume, options.gzip);
        });
        return {path};
    }
    replaceFileAtomically(dataPath,
                          [&](const fs::path& tmp) { writeFile(tmp, dataPath, "", &volume, options.gzip); });
    replaceFileAtomically(path, [&](const fs::path& tmp) {
        writeFile(tmp, path, headerText(volume, options.gzip, dataPath.filename().string()), nullptr, false);
    });
    return {path, dataPath};
}

} // namespace renderer
