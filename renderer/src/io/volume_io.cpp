// Raw and NRRD readers and the dispatch by file name (loadVolume). The other formats live in
// volume_io_<format>.cpp; what they share (size checks, decompression, voxel decoding) in
// volume_io_common.cpp. Every failure is a LoadError naming the file and field.
#include "renderer/io/volume_io.h"

#include "renderer/errors.h"
#include "volume_io_detail.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <string_view>

namespace renderer {
namespace {

using namespace io;

constexpr size_t kMaxHeaderLineBytes = size_t(1) << 16;   // longer "lines" mean binary data, not a header

// == NRRD header

std::optional<VoxelType> nrrdType(std::string_view value) {
    // NRRD allows several spellings per type; whitespace inside ("unsigned  short") is normalised.
    std::string key;
    for (std::string_view word : splitWords(value)) key += (key.empty() ? "" : " ") + lower(word);
    static const std::map<std::string, VoxelType, std::less<>> kTypes = {
        {"uchar", VoxelType::U8},
        {"unsigned char", VoxelType::U8},
        {"uint8", VoxelType::U8},
        {"uint8_t", VoxelType::U8},
        {"short", VoxelType::I16},
        {"short int", VoxelType::I16},
        {"signed short", VoxelType::I16},
        {"signed short int", VoxelType::I16},
        {"int16", VoxelType::I16},
        {"int16_t", VoxelType::I16},
        {"ushort", VoxelType::U16},
        {"unsigned short", VoxelType::U16},
        {"unsigned short int", VoxelType::U16},
        {"uint16", VoxelType::U16},
        {"uint16_t", VoxelType::U16},
        {"float", VoxelType::F32},
    };
    const auto it = kTypes.find(key);
    return it == kTypes.end() ? std::nullopt : std::optional(it->second);
}

struct NrrdField {
    std::string name;   // as spelled in the file, for messages
    std::string value;
    int line = 0;
};

struct NrrdHeader {
    std::map<std::string, NrrdField> fields;   // keyed by lower-case name without spaces ("datafile")
    std::streamoff dataOffset = -1;            // start of attached data; -1 when the header ran to EOF

    const NrrdField* find(const std::string& key) const {
        const auto it = fields.find(key);
        return it == fields.end() ? nullptr : &it->second;
    }
};

enum class LineStatus { Ok, End, TooLong };

LineStatus readLine(std::istream& in, std::string& line) {
    line.clear();
    for (int c; (c = in.get()) != std::char_traits<char>::eof();) {
        if (c == '\n') break;
        if (line.size() == kMaxHeaderLineBytes) return LineStatus::TooLong;
        line += char(c);
    }
    if (line.empty() && in.eof()) return LineStatus::End;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return LineStatus::Ok;
}

NrrdHeader readNrrdHeader(const fs::path& path) {
    std::ifstream in = openFile(path, path, "");
    std::string line;
    const LineStatus first = readLine(in, line);
    const bool magicOk = first == LineStatus::Ok && line.size() == 8 && line.starts_with("NRRD000") &&
                         line[7] >= '1' && line[7] <= '5';
    if (!magicOk)
        fail(path, "",
             "not a NRRD file: first line is " + excerpt(first == LineStatus::End ? "" : line) +
                 ", expected NRRD0001..NRRD0005");

    NrrdHeader header;
    for (int lineNo = 2;; ++lineNo) {
        const LineStatus status = readLine(in, line);
        if (status == LineStatus::End) break;
        if (status == LineStatus::TooLong)
            fail(path, "",
                 "line " + std::to_string(lineNo) + " is longer than " + std::to_string(kMaxHeaderLineBytes) +
                     " bytes; is there a blank line missing before the data?");
        if (trim(line).empty()) {   // a blank line ends the header; attached data follows it
            header.dataOffset = in.tellg();
            break;
        }
        if (line.starts_with('#')) continue;
        const size_t colon = line.find(':');
        if (colon == std::string::npos || colon == 0)
            fail(path, "", "line " + std::to_string(lineNo) + " is not 'field: value': " + excerpt(line));
        if (colon + 1 < line.size() && line[colon + 1] == '=')
            continue;   // "key:=value" pairs carry no geometry
        NrrdField field{std::string(trim(std::string_view(line).substr(0, colon))),
                        std::string(trim(std::string_view(line).substr(colon + 1))), lineNo};
        std::string key;
        for (char c : lower(field.name))
            if (c != ' ') key += c;   // "data file" and "datafile" are the same field
        const auto [it, inserted] = header.fields.emplace(key, field);
        if (!inserted)
            fail(path, field.name,
                 "appears twice (lines " + std::to_string(it->second.line) + " and " +
                     std::to_string(lineNo) + ")");
    }
    return header;
}

// Parses NRRD vectors such as "(1,0,0) (0,1,0) none"; a "none" entry comes back empty.
std::vector<std::vector<double>> parseVectors(const fs::path& path, const NrrdField& field) {
    std::vector<std::vector<double>> vectors;
    std::string_view rest = trim(field.value);
    while (!rest.empty()) {
        if (lower(rest.substr(0, 4)) == "none") {
            vectors.emplace_back();
            rest = trim(rest.substr(4));
            continue;
        }
        const size_t close = rest.find(')');
        if (rest.front() != '(' || close == std::string_view::npos)
            fail(path, field.name, "expected vectors like (1,0,0), got " + excerpt(field.value));
        std::vector<double>& v = vectors.emplace_back();
        std::string_view inner = rest.substr(1, close - 1);
        while (true) {
            const size_t comma = inner.find(',');
            const auto number = parseDouble(trim(inner.substr(0, comma)));
            if (!number || !std::isfinite(*number))
                fail(path, field.name,
                     "component " + excerpt(trim(inner.substr(0, comma))) + " is not a finite number");
            v.push_back(*number);
            if (comma == std::string_view::npos) break;
            inner = inner.substr(comma + 1);
        }
        rest = trim(rest.substr(close + 1));
    }
    return vectors;
}

// Spacing from 'spacings' or the lengths of the 'space directions' vectors; `directions` gets the
// unit vectors (identity when the header gives none).
glm::dvec3 nrrdSpacing(const fs::path& path, const NrrdHeader& header, glm::dmat3& directionsOut) {
    const NrrdField* spacings = header.find("spacings");
    const NrrdField* directions = header.find("spacedirections");
    if (spacings && directions)
        fail(path, spacings->name,
             "cannot be given together with 'space directions' (NRRD allows one per axis)");
    glm::dvec3 spacing(1.0);   // NRRD leaves spacing optional; unit spacing is the format's own default
    if (spacings) {
        const auto words = splitWords(spacings->value);
        if (words.size() != 3)
            fail(path, spacings->name,
                 "has " + std::to_string(words.size()) + " values, expected 3 (dimension: 3)");
        for (int axis = 0; axis < 3; ++axis) {
            const auto s = parseDouble(words[size_t(axis)]);
            if (!s || !std::isfinite(*s) || *s <= 0)
                fail(path, spacings->name,
                     "spacing " + excerpt(words[size_t(axis)]) + " on axis " + std::to_string(axis) +
                         " must be a finite positive number");
            spacing[axis] = *s;
        }
    } else if (directions) {
        // The step lengths are the spacing; their unit vectors are kept as Volume::directions.
        const auto vectors = parseVectors(path, *directions);
        if (vectors.size() != 3)
            fail(path, directions->name,
                 "has " + std::to_string(vectors.size()) + " vectors, expected 3 (dimension: 3)");
        for (int axis = 0; axis < 3; ++axis) {
            const auto& v = vectors[size_t(axis)];
            if (v.empty())
                fail(path, directions->name,
                     "axis " + std::to_string(axis) + " is 'none'; all 3 axes must be spatial");
            double lengthSq = 0;
            for (double c : v) lengthSq += c * c;
            if (!(lengthSq > 0) || !std::isfinite(lengthSq))
                fail(path, directions->name, "axis " + std::to_string(axis) + " has zero length");
            spacing[axis] = std::sqrt(lengthSq);
            if (v.size() == 3) directionsOut[axis] = glm::dvec3(v[0], v[1], v[2]) / spacing[axis];
        }
    }
    return checkedSpacing(path, spacings ? spacings->name : directions ? directions->name : "spacings", spacing);
}

size_t nonNegativeField(const fs::path& path, const NrrdField* field) {
    if (!field) return 0;
    const auto v = parseInt(field->value);
    if (v == -1)
        fail(path, field->name, "-1 (data at the end of the file) is not supported; give the byte count");
    if (!v || *v < 0) fail(path, field->name, excerpt(field->value) + " is not a non-negative integer");
    return size_t(*v);
}

} // namespace

std::optional<RawOptions> rawOptionsFromFileName(const std::filesystem::path& path) {
    // "<anything>_<W>x<H>x<D>_<type>.raw[.gz]", e.g. headsq_64x64x93_int16.raw
    const std::string file = path.filename().string();
    std::string_view name = file;
    if (name.ends_with(".gz")) name.remove_suffix(3);
    if (!name.ends_with(".raw")) return std::nullopt;
    name.remove_suffix(4);
    const size_t typeSep = name.rfind('_');
    if (typeSep == std::string_view::npos) return std::nullopt;
    const size_t dimsSep = name.substr(0, typeSep).rfind('_');
    if (dimsSep == std::string_view::npos) return std::nullopt;

    static const std::map<std::string, VoxelType, std::less<>> kTypes = {{"uint8", VoxelType::U8},
                                                                         {"uint16", VoxelType::U16},
                                                                         {"int16", VoxelType::I16},
                                                                         {"float32", VoxelType::F32},
                                                                         {"float", VoxelType::F32}};
    const auto type = kTypes.find(name.substr(typeSep + 1));
    if (type == kTypes.end()) return std::nullopt;

    RawOptions options;
    options.type = type->second;
    std::string_view dims = name.substr(dimsSep + 1, typeSep - dimsSep - 1);
    for (int axis = 0; axis < 3; ++axis) {
        const size_t x = axis < 2 ? dims.find('x') : dims.size();
        if (x == std::string_view::npos) return std::nullopt;
        int v = 0;
        const auto [end, ec] = std::from_chars(dims.data(), dims.data() + x, v);
        if (ec != std::errc() || end != dims.data() + x || v <= 0) return std::nullopt;
        options.dims[axis] = v;
        dims = dims.substr(std::min(x + 1, dims.size()));
    }
    return options;
}

Volume loadRaw(const std::filesystem::path& path, const RawOptions& options, const ProgressCallback& progress) {
    Volume volume;
    volume.dims = checkedDims(path, "dims", options.dims.x, options.dims.y, options.dims.z);
    for (int axis = 0; axis < 3; ++axis)
        if (!std::isfinite(options.spacing[axis]) || options.spacing[axis] <= 0)
            fail(path, "spacing",
                 "axis " + std::to_string(axis) + " is " + std::to_string(options.spacing[axis]) +
                     ", expected a finite positive number");

    DataSource src{.file = path,
                   .byteSkip = options.headerBytes,
                   .exact = true,
                   .endian = options.endian,
                   .sizeField = "dims",
                   .progress = progress};
    // Compressed when named so or when it starts with the gzip magic bytes 1f 8b.
    std::ifstream probe = openFile(path, path, "");
    unsigned char magic[2] = {0, 0};
    probe.read(reinterpret_cast<char*>(magic), 2);
    if (lower(path.filename().string()).ends_with(".gz") || (magic[0] == 0x1f && magic[1] == 0x8b))
        src.compression = Compression::Zlib;

    volume.name = volumeName(path);
    volume.type = options.type;
    volume.spacing = checkedSpacing(path, "spacing", options.spacing);
    volume.values = readVoxels(path, src, volume.dims, volume.type);
    updateRange(volume);
    return volume;
}

Volume loadNrrd(const std::filesystem::path& path, const ProgressCallback& progress) {
    // 1. Header lines into fields (duplicates and malformed lines rejected there).
    const NrrdHeader header = readNrrdHeader(path);
    const auto require = [&](const std::string& key, const std::string& name) -> const NrrdField& {
        const NrrdField* field = header.find(key);
        if (!field) fail(path, name, "missing (a NRRD header must give it)");
        return *field;
    };

    // 2. Dimension, type and sizes, checked before anything is allocated.
    const NrrdField& dimension = require("dimension", "dimension");
    if (parseInt(dimension.value) != 3)
        fail(path, dimension.name, excerpt(dimension.value) + ", expected 3 (only 3D volumes are supported)");
    const NrrdField& typeField = require("type", "type");
    const auto type = nrrdType(typeField.value);
    if (!type)
        fail(path, typeField.name,
             excerpt(typeField.value) +
                 " is not supported (supported: uchar, unsigned char, uint8, uint8_t; short, "
                 "signed short, int16, int16_t; ushort, unsigned short, uint16, uint16_t; float)");
    const NrrdField& sizesField = require("sizes", "sizes");
    const auto words = splitWords(sizesField.value);
    if (words.size() != 3)
        fail(path, sizesField.name,
             "has " + std::to_string(words.size()) + " values, expected 3 (dimension: 3)");
    long long sizes[3];
    for (int axis = 0; axis < 3; ++axis) {
        const auto s = parseInt(words[size_t(axis)]);
        if (!s) fail(path, sizesField.name, excerpt(words[size_t(axis)]) + " is not an integer");
        sizes[axis] = *s;
    }

    Volume volume;
    volume.name = volumeName(path);
    volume.type = *type;
    volume.dims = checkedDims(path, sizesField.name, sizes[0], sizes[1], sizes[2]);

    // 3. Geometry: spacing from 'spacings' or the lengths of 'space directions'; origin from 'space origin'.
    volume.spacing = nrrdSpacing(path, header, volume.directions);
    if (const NrrdField* origin = header.find("spaceorigin")) {
        const auto vectors = parseVectors(path, *origin);
        if (vectors.size() != 1 || vectors[0].size() != 3)
            fail(path, origin->name, "expected one 3-vector such as (0,0,0), got " + excerpt(origin->value));
        volume.origin = {vectors[0][0], vectors[0][1], vectors[0][2]};
    }

    // 4. Storage: encoding, endianness (multi-byte types only), skips and the data's location.
    DataSource src;
    src.progress = progress;
    src.sizeField = sizesField.name;
    const NrrdField& encoding = require("encoding", "encoding");
    const std::string enc = lower(encoding.value);
    if (enc == "gzip" || enc == "gz")
        src.compression = Compression::Zlib;
    else if (enc == "bzip2" || enc == "bz2")
        src.compression = Compression::Bzip2;
    else if (enc != "raw")
        fail(path, encoding.name,
             excerpt(encoding.value) + " is not supported (supported: raw, gzip" +
                 (bzip2Available() ? ", bzip2)" : "; bzip2 needs a build with libbz2)"));
    if (src.compression == Compression::Bzip2 && !bzip2Available())
        fail(path, encoding.name, "bzip2 needs a build with libbz2 (apt install libbz2-dev, rebuild)");
    if (const NrrdField* endian = header.find("endian")) {
        const std::string e = lower(endian->value);
        if (e != "little" && e != "big")
            fail(path, endian->name, excerpt(endian->value) + " is not 'little' or 'big'");
        src.endian = e == "little" ? Endian::Little : Endian::Big;
    } else if (voxelTypeBytes(*type) > 1) {
        fail(path, "endian", std::string("missing; required for ") + voxelTypeName(*type) + " data");
    }
    src.byteSkip = nonNegativeField(path, header.find("byteskip"));
    src.lineSkip = nonNegativeField(path, header.find("lineskip"));
    if (const NrrdField* dataFile = header.find("datafile")) {
        const auto parts = splitWords(dataFile->value);
        if (parts.empty()) fail(path, dataFile->name, "is empty");
        if (parts[0] == "LIST" || (parts.size() >= 4 && dataFile->value.find('%') != std::string::npos))
            fail(path, dataFile->name, "lists of data files are not supported; join them into one file");
        const fs::path file(dataFile->value);
        src.file = file.is_absolute() ? file : path.parent_path() / file;   // relative to the header's folder
    } else if (header.dataOffset >= 0) {
        src.file = path;
        src.offset = header.dataOffset;
    } else {
        fail(path, "data file", "missing, and no blank line with data after the header");
    }

    // 5. Voxels.
    volume.values = readVoxels(path, src, volume.dims, volume.type);
    updateRange(volume);
    return volume;
}

const std::vector<std::string>& volumeFileExtensions() {
    static const std::vector<std::string> extensions{".nrrd", ".nhdr", ".mhd", ".mha",  ".nii", ".nii.gz",
                                                     ".slc",  ".dat",  ".tif", ".tiff", ".raw", ".raw.gz"};
    return extensions;
}

const char* supportedVolumeTypes() {
    return ".nrrd, .nhdr, .mhd, .mha, .nii, .nii.gz, .slc, .dat, .tif, .tiff, .raw, .raw.gz, a folder of "
           ".tif/.png slices or a slice pattern such as slice_%03d.png";
}

namespace {
Volume loadVolumeByType(const std::filesystem::path& path, const std::optional<RawOptions>& raw,
                        const ProgressCallback& progress);
} // namespace

Volume loadVolume(const std::filesystem::path& path, const std::optional<RawOptions>& raw,
                  const ProgressCallback& progress) {
    // The budget check keeps lying headers from allocating; an allocation that still fails (memory
    // taken by others meanwhile) is named here rather than reaching the user as a bare std::bad_alloc.
    try {
        return loadVolumeByType(path, raw, progress);
    } catch (const std::bad_alloc&) {
        fail(path, "", "out of memory while reading the voxels (the memory budget is " +
                           std::to_string(volumeMemoryBudget() / kMiB) + " MiB; less is free now)");
    }
}

namespace {
Volume loadVolumeByType(const std::filesystem::path& path, const std::optional<RawOptions>& raw,
                        const ProgressCallback& progress) {
    std::error_code ec;
    const std::string name = lower(path.filename().string());
    if (name.find('%') != std::string::npos) return loadImageStack(path, progress);
    if (!fs::exists(path, ec)) fail(path, "", "cannot open: no such file");
    if (fs::is_directory(path, ec)) return loadImageStack(path, progress);
    if (name.ends_with(".nrrd") || name.ends_with(".nhdr")) return loadNrrd(path, progress);
    if (name.ends_with(".mhd") || name.ends_with(".mha")) return loadMetaImage(path, progress);
    if (name.ends_with(".nii") || name.ends_with(".nii.gz")) return loadNifti(path, progress);
    if (name.ends_with(".slc")) return loadSlc(path, progress);
    if (name.ends_with(".dat")) return loadDat(path, progress);
    if (name.ends_with(".tif") || name.ends_with(".tiff")) return loadImageStack(path, progress);
    if (name.ends_with(".raw") || name.ends_with(".raw.gz")) {
        const std::optional<RawOptions> options = raw ? raw : rawOptionsFromFileName(path);
        if (!options)
            fail(path, "",
                 "raw file without dims and type: give --raw-dims and --raw-type, or rename it like "
                 "name_256x256x128_uint8.raw (types: uint8, uint16, int16, float32)");
        return loadRaw(path, *options, progress);
    }
    fail(path, "", "unknown file type " + excerpt(path.extension().string()) + " (supported: " +
                       supportedVolumeTypes() + ")");
}
} // namespace

Volume loadVolumeInWorldFrame(const std::filesystem::path& path, const std::optional<RawOptions>& raw,
                              const ProgressCallback& progress) {
    Volume volume = loadVolume(path, raw, progress);
    try {
        return alignedToWorldAxes(std::move(volume));
    } catch (const LoadError& e) {   // it knows the volume by name only
        throw LoadError(path.string(), e.field(), e.reason());
    }
}

} // namespace renderer
