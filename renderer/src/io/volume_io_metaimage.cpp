// MetaImage (ITK/VTK): "Key = Value" header lines ending with ElementDataFile, voxels either after
// the header (.mha, "LOCAL") or in a separate file (.mhd). zlib-compressed data, spacing, offset and
// TransformMatrix are read; ASCII data, multi-channel images and file lists are refused by name.
#include "renderer/io/volume_io.h"

#include "volume_io_detail.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace renderer {
namespace {

using namespace io;

constexpr size_t kMaxLineBytes = size_t(1) << 16;
constexpr int kMaxHeaderLines = 4096;

struct MetaField {
    std::string key; // as spelled in the file
    std::string value;
    int line = 0;
};

struct MetaHeader {
    std::map<std::string, MetaField> fields; // keyed by lower-case name
    std::streamoff dataOffset = 0;           // just after the ElementDataFile line

    const MetaField* find(const std::string& key) const {
        const auto it = fields.find(key);
        return it == fields.end() ? nullptr : &it->second;
    }
};

MetaHeader readMetaHeader(const fs::path& path) {
    std::ifstream in = openFile(path, path, "");
    MetaHeader header;
    std::string line;
    for (int lineNo = 1;; ++lineNo) {
        line.clear();
        int c = 0;
        while ((c = in.get()) != std::char_traits<char>::eof() && c != '\n') {
            if (line.size() == kMaxLineBytes)
                fail(path, "",
                     "line " + std::to_string(lineNo) + " is longer than " + std::to_string(kMaxLineBytes) +
                         " bytes: not a MetaImage header");
            line += char(c);
        }
        if (c == std::char_traits<char>::eof() && line.empty())
            fail(path, "ElementDataFile", "missing: the header ended without it (it must be the last field)");
        if (lineNo > kMaxHeaderLines)
            fail(path, "",
                 "more than " + std::to_string(kMaxHeaderLines) + " header lines without ElementDataFile");
        const std::string_view text = trim(line);
        if (text.empty()) continue;
        const size_t eq = text.find('=');
        if (eq == std::string_view::npos || eq == 0)
            fail(path, "",
                 "line " + std::to_string(lineNo) + " is not 'Key = Value': " + excerpt(text) +
                     (lineNo == 1 ? " (not a MetaImage file?)" : ""));
        MetaField field{std::string(trim(text.substr(0, eq))), std::string(trim(text.substr(eq + 1))),
                        lineNo};
        const std::string key = lower(field.key);
        const auto [it, inserted] = header.fields.emplace(key, field);
        if (!inserted)
            fail(path, field.key,
                 "appears twice (lines " + std::to_string(it->second.line) + " and " +
                     std::to_string(lineNo) + ")");
        if (key == "elementdatafile") {
            header.dataOffset = in.tellg();
            if (header.dataOffset < 0) header.dataOffset = fileSize(path, path, ""); // ended at EOF
            return header;
        }
    }
}

std::vector<double> numbers(const fs::path& path, const MetaField& field, size_t expected) {
    const auto words = splitWords(field.value);
    if (words.size() != expected)
        fail(path, field.key,
             "has " + std::to_string(words.size()) + " values, expected " + std::to_string(expected) +
                 " (NDims = 3)");
    std::vector<double> out;
    for (std::string_view w : words) {
        const auto v = parseDouble(w);
        if (!v || !std::isfinite(*v)) fail(path, field.key, excerpt(w) + " is not a finite number");
        out.push_back(*v);
    }
    return out;
}

bool boolean(const fs::path& path, const MetaField& field) {
    const std::string v = lower(field.value);
    if (v == "true" || v == "1") return true;
    if (v == "false" || v == "0") return false;
    fail(path, field.key, excerpt(field.value) + ", expected True or False");
}

} // namespace

Volume loadMetaImage(const std::filesystem::path& path, const ProgressCallback& progress) {
    // 1. Header fields up to ElementDataFile.
    const MetaHeader header = readMetaHeader(path);
    const auto require = [&](const std::string& key, const std::string& name) -> const MetaField& {
        const MetaField* field = header.find(key);
        if (!field) fail(path, name, "missing (a MetaImage header must give it)");
        return *field;
    };
    if (const MetaField* type = header.find("objecttype"); type && lower(type->value) != "image")
        fail(path, type->key, excerpt(type->value) + ", expected Image");

    // 2. Geometry: NDims, DimSize, spacing, offset and direction, checked before any allocation.
    const MetaField& ndims = require("ndims", "NDims");
    if (parseInt(ndims.value) != 3)
        fail(path, ndims.key, excerpt(ndims.value) + ", expected 3 (only 3D volumes are supported)");
    const MetaField& dimSize = require("dimsize", "DimSize");
    const auto dimWords = splitWords(dimSize.value);
    if (dimWords.size() != 3)
        fail(path, dimSize.key, "has " + std::to_string(dimWords.size()) + " values, expected 3 (NDims = 3)");
    long long sizes[3];
    for (int axis = 0; axis < 3; ++axis) {
        const auto s = parseInt(dimWords[size_t(axis)]);
        if (!s) fail(path, dimSize.key, excerpt(dimWords[size_t(axis)]) + " is not an integer");
        sizes[axis] = *s;
    }
    Volume volume;
    volume.name = volumeName(path);
    volume.dims = checkedDims(path, dimSize.key, sizes[0], sizes[1], sizes[2]);
    const MetaField* spacing = header.find("elementspacing");
    if (!spacing) spacing = header.find("elementsize"); // older writers give only the voxel size
    if (spacing) {
        const auto s = numbers(path, *spacing, 3);
        volume.spacing = checkedSpacing(path, spacing->key, {s[0], s[1], s[2]});
    }
    for (const char* key : {"offset", "position", "origin"}) {
        if (const MetaField* offset = header.find(key)) {
            const auto o = numbers(path, *offset, 3);
            volume.origin = {o[0], o[1], o[2]};
            break;
        }
    }
    for (const char* key : {"transformmatrix", "rotation", "orientation"}) {
        if (const MetaField* matrix = header.find(key)) {
            // Written axis by axis: the first three numbers are the x axis' direction (as ITK reads them).
            const auto m = numbers(path, *matrix, 9);
            glm::dmat3 d;
            for (int axis = 0; axis < 3; ++axis)
                d[axis] = {m[size_t(3 * axis)], m[size_t(3 * axis + 1)], m[size_t(3 * axis + 2)]};
            if (!(std::abs(glm::determinant(d)) > 1e-6))
                fail(path, matrix->key, excerpt(matrix->value) + " is singular, expected a rotation matrix");
            volume.directions = d;
            break;
        }
    }

    // 3. Voxel type, channels and byte order.
    const MetaField& elementType = require("elementtype", "ElementType");
    static const std::map<std::string, VoxelType> kTypes = {{"MET_UCHAR", VoxelType::U8},
                                                            {"MET_USHORT", VoxelType::U16},
                                                            {"MET_SHORT", VoxelType::I16},
                                                            {"MET_FLOAT", VoxelType::F32}};
    const auto type = kTypes.find(elementType.value);
    if (type == kTypes.end())
        fail(path, elementType.key,
             excerpt(elementType.value) +
                 " is not supported (supported: MET_UCHAR, MET_USHORT, MET_SHORT, MET_FLOAT)");
    volume.type = type->second;
    if (const MetaField* channels = header.find("elementnumberofchannels");
        channels && parseInt(channels->value) != 1)
        fail(path, channels->key, excerpt(channels->value) + ", expected 1 (scalar volumes only)");
    if (const MetaField* binary = header.find("binarydata"); binary && !boolean(path, *binary))
        fail(path, binary->key, "ASCII voxel data is not supported, expected True");

    DataSource src;
    src.progress = progress;
    src.sizeField = dimSize.key;
    for (const char* key : {"binarydatabyteordermsb", "elementbyteordermsb"})
        if (const MetaField* msb = header.find(key))
            src.endian = boolean(path, *msb) ? Endian::Big : Endian::Little;
    const MetaField* compressed = header.find("compresseddata");
    if (compressed && boolean(path, *compressed)) src.compression = Compression::Zlib;
    if (const MetaField* size = header.find("compresseddatasize")) {
        const auto bytes = parseInt(size->value);
        if (!bytes || *bytes < 0)
            fail(path, size->key, excerpt(size->value) + " is not a non-negative integer");
    }

    // 4. Where the voxels are: after the header (LOCAL) or in the named file, after HeaderSize bytes.
    const MetaField& dataFile = *header.find("elementdatafile");
    if (dataFile.value.empty()) fail(path, dataFile.key, "is empty, expected LOCAL or a file name");
    if (dataFile.value == "LOCAL") {
        src.file = path;
        src.offset = header.dataOffset;
    } else {
        if (dataFile.value.starts_with("LIST") || dataFile.value.find('%') != std::string::npos)
            fail(path, dataFile.key,
                 excerpt(dataFile.value) + ": file lists are not supported; join the slices into one file");
        const fs::path file(dataFile.value);
        src.file = file.is_absolute() ? file : path.parent_path() / file;
    }
    if (const MetaField* headerSize = header.find("headersize")) {
        const auto skip = parseInt(headerSize->value);
        if (skip == -1) {
            // -1: the voxels are the last bytes of the file, whatever precedes them.
            if (src.compression != Compression::None)
                fail(path, headerSize->key, "-1 needs uncompressed data (CompressedData = False)");
            const uintmax_t size = fileSize(src.file, path, dataFile.key);
            const uintmax_t needed = uintmax_t(volume.voxelCount()) * voxelTypeBytes(volume.type);
            const uintmax_t start = uintmax_t(src.offset);
            if (size < start + needed)
                fail(path, "data",
                     "data file '" + src.file.string() + "' has " + std::to_string(size) +
                         " bytes, expected at least " + std::to_string(needed) + " (" +
                         layoutText(volume.dims, volume.type) + ")");
            src.offset = std::streamoff(size - needed);
        } else if (!skip || *skip < 0) {
            fail(path, headerSize->key, excerpt(headerSize->value) + " is not a byte count (or -1)");
        } else {
            // Bytes of the file before the (possibly compressed) voxels.
            const uintmax_t size = fileSize(src.file, path, dataFile.key);
            if (uintmax_t(*skip) > size - std::min<uintmax_t>(size, uintmax_t(src.offset)))
                fail(path, headerSize->key,
                     std::to_string(*skip) + " bytes to skip, but '" + src.file.string() + "' has only " +
                         std::to_string(size) + " bytes");
            src.offset += std::streamoff(*skip);
        }
    }

    // 5. Voxels.
    volume.values = readVoxels(path, src, volume.dims, volume.type);
    updateRange(volume);
    return volume;
}

} // namespace renderer
