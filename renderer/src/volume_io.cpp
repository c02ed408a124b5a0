// Raw and NRRD readers: header parsing, size checks, gzip inflation and conversion of voxel bytes to
// floats. Every failure is a LoadError naming the file and field; the Volume itself knows no format.
#include "renderer/volume_io.h"

#include "renderer/errors.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <string_view>

namespace renderer {
namespace {

namespace fs = std::filesystem;

constexpr size_t kChunkBytes = size_t(1) << 16;   // read/inflate granularity; a multiple of every voxel size
constexpr size_t kMaxHeaderLineBytes = size_t(1) << 16;   // longer "lines" mean binary data, not a header

[[noreturn]] void fail(const fs::path& path, const std::string& field, const std::string& reason) {
    throw LoadError(path.string(), field, reason);
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string_view trim(std::string_view s) {
    const auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> splitWords(std::string_view s) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        const size_t start = i;
        while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        if (i > start) words.push_back(s.substr(start, i - start));
    }
    return words;
}

// Quotes text read from a file for an error message: binary junk becomes '?', long lines are cut.
std::string excerpt(std::string_view s) {
    std::string out = "'";
    for (char c : s.substr(0, 60)) out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    return out + (s.size() > 60 ? "...'" : "'");
}

std::optional<long long> parseInt(std::string_view s) {
    long long v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return v;
}

std::optional<double> parseDouble(std::string_view s) {
    double v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return v;
}

std::string layoutText(glm::ivec3 dims, VoxelType type) {
    return std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" + std::to_string(dims.z) + " " +
           voxelTypeName(type);
}

// Checks three axis sizes before anything is allocated: each positive and fitting an int, and their
// product within kMaxVoxels (so voxels * 4 bytes cannot overflow size_t either).
glm::ivec3 checkedDims(const fs::path& path, const std::string& field, long long x, long long y,
                       long long z) {
    const long long sizes[3] = {x, y, z};
    for (long long s : sizes)
        if (s <= 0) fail(path, field, "size " + std::to_string(s) + " must be a positive integer");
    const std::string text = std::to_string(x) + " x " + std::to_string(y) + " x " + std::to_string(z);
    unsigned long long product = 1;
    for (long long s : sizes) {
        if (s > INT_MAX || product > kMaxVoxels / (unsigned long long)s)
            fail(path, field, text + " voxels is more than the " + std::to_string(kMaxVoxels) + " supported");
        product *= (unsigned long long)s;
    }
    return {int(x), int(y), int(z)};
}

// The name shown for a volume: the file name without .gz and then .raw/.nrrd/.nhdr.
std::string volumeName(const fs::path& path) {
    std::string name = path.filename().string();
    for (std::string_view ext : {".gz", ".raw", ".nrrd", ".nhdr"}) {
        if (name.size() > ext.size() && lower(name).ends_with(ext)) name.resize(name.size() - ext.size());
    }
    return name;
}

std::ifstream openFile(const fs::path& file, const fs::path& report, const std::string& field) {
    const std::string what = file == report ? "cannot open: " : "cannot open '" + file.string() + "': ";
    std::error_code ec;
    if (fs::is_directory(file, ec)) fail(report, field, what + "is a directory");
    std::ifstream in(file, std::ios::binary);
    if (!in) fail(report, field, what + std::strerror(errno));
    return in;
}

// Sequential bytes of the voxel stream, inflated on the fly when the data is gzip-compressed.
class ByteReader {
public:
    ByteReader(std::ifstream& in, bool gzip, fs::path report)
        : m_in(in), m_gzip(gzip), m_report(std::move(report)) {
        // 16 + MAX_WBITS: expect a gzip wrapper (header + CRC), not a bare zlib stream.
        if (m_gzip && inflateInit2(&m_zs, 16 + MAX_WBITS) != Z_OK)
            fail(m_report, "data", "cannot start zlib");
    }
    ~ByteReader() {
        if (m_gzip) inflateEnd(&m_zs);
    }
    ByteReader(const ByteReader&) = delete;
    ByteReader& operator=(const ByteReader&) = delete;

    // Fills dst with n bytes; fewer only when the file (or the gzip stream) ended first.
    size_t read(unsigned char* dst, size_t n) {
        if (!m_gzip) {
            m_in.read(reinterpret_cast<char*>(dst), std::streamsize(n));
            return size_t(m_in.gcount());
        }
        size_t got = 0;
        while (got < n && !m_ended) {
            if (m_zs.avail_in == 0) {
                m_in.read(reinterpret_cast<char*>(m_buffer.data()), std::streamsize(m_buffer.size()));
                m_zs.next_in = m_buffer.data();
                m_zs.avail_in = uInt(m_in.gcount());
                if (m_zs.avail_in == 0) break;   // the file ended inside the stream: truncated
            }
            const size_t want = std::min(n - got, kChunkBytes);   // avail_out is a 32-bit uInt
            m_zs.next_out = dst + got;
            m_zs.avail_out = uInt(want);
            const int rc = inflate(&m_zs, Z_NO_FLUSH);
            got += want - m_zs.avail_out;
            if (rc == Z_STREAM_END) {
                // gzip allows concatenated members (cat a.gz b.gz); carry on when more input follows.
                if (m_zs.avail_in == 0 && m_in.peek() == std::char_traits<char>::eof())
                    m_ended = true;
                else
                    inflateReset(&m_zs);
            } else if (rc != Z_OK && rc != Z_BUF_ERROR) {
                fail(m_report, "data",
                     std::string("gzip stream is corrupt: ") + (m_zs.msg ? m_zs.msg : zError(rc)));
            }
        }
        return got;
    }

private:
    std::ifstream& m_in;
    bool m_gzip;
    fs::path m_report;
    z_stream m_zs{};
    bool m_ended = false;
    std::vector<unsigned char> m_buffer = std::vector<unsigned char>(kChunkBytes);
};

void decodeVoxels(const unsigned char* bytes, size_t count, VoxelType type, Endian endian, float* out) {
    const bool little = endian == Endian::Little;
    for (size_t i = 0; i < count; ++i) {
        const unsigned char* b = bytes + i * voxelTypeBytes(type);
        switch (type) {
        case VoxelType::U8: out[i] = float(b[0]); break;
        case VoxelType::U16: out[i] = float(uint16_t(little ? b[0] | b[1] << 8 : b[1] | b[0] << 8)); break;
        case VoxelType::I16:
            out[i] = float(int16_t(uint16_t(little ? b[0] | b[1] << 8 : b[1] | b[0] << 8)));
            break;
        case VoxelType::F32: {
            const uint32_t b0 = b[little ? 0 : 3], b1 = b[little ? 1 : 2], b2 = b[little ? 2 : 1],
                           b3 = b[little ? 3 : 0];
            out[i] = std::bit_cast<float>(b0 | b1 << 8 | b2 << 16 | b3 << 24);
            break;
        }
        }
    }
}

// Where the voxel bytes are and how they are stored.
struct DataSource {
    fs::path file;               // the file holding the bytes (the header itself when attached)
    std::streamoff offset = 0;   // where the stored (possibly compressed) data starts in `file`
    size_t lineSkip = 0;         // text lines to skip from `offset` before the data (NRRD "line skip")
    size_t byteSkip = 0;         // bytes to drop before the voxels, counted after decompression
    bool gzip = false;
    bool exact = false;   // trailing bytes are an error (raw files) instead of being ignored (NRRD)
    Endian endian = Endian::Little;
};

// Reads dims/type voxels from `src` into floats. `report` is the file named in errors.
std::vector<float> readVoxels(const fs::path& report, const DataSource& src, glm::ivec3 dims,
                              VoxelType type) {
    const size_t count = size_t(dims.x) * size_t(dims.y) * size_t(dims.z);   // checkedDims() bounded it
    const size_t needed = count * voxelTypeBytes(type);
    const std::string where = src.file == report ? "file" : "data file '" + src.file.string() + "'";
    const std::string expected =
        std::to_string(needed) + " bytes (" + layoutText(dims, type) +
        (src.byteSkip ? " after a " + std::to_string(src.byteSkip) + "-byte skip)" : ")");

    // 1. Open and find where the stored data starts (after the header and any skipped lines).
    std::ifstream in = openFile(src.file, report, src.file == report ? "" : "data file");
    in.seekg(src.offset);
    for (size_t line = 0; line < src.lineSkip; ++line) {
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
        if (!in)
            fail(report, "line skip", where + " has fewer than " + std::to_string(src.lineSkip) + " lines");
    }
    const std::streamoff start = in.tellg();
    if (start < 0) fail(report, "data", "cannot seek in " + where);

    // 2. Uncompressed data: compare the file size with what the header promises before allocating.
    if (!src.gzip) {
        std::error_code ec;
        const uintmax_t fileSize = fs::file_size(src.file, ec);
        if (ec) fail(report, "data", "cannot read the size of " + where + ": " + ec.message());
        const uintmax_t available = fileSize - uintmax_t(start);
        const std::string after = start > 0 ? " after the header" : "";
        if (available < src.byteSkip || available - src.byteSkip < needed)
            fail(report, "data",
                 where + " has " + std::to_string(available) + " bytes" + after + ", expected " + expected);
        if (src.exact && available - src.byteSkip > needed)
            fail(report, "data",
                 where + " has " + std::to_string(available) + " bytes" + after + ", expected " + expected +
                     "; " + std::to_string(available - src.byteSkip - needed) + " trailing bytes");
        in.seekg(std::streamoff(src.byteSkip), std::ios::cur);
    }

    // 3. Stream the data in chunks: drop the byte skip, then decode each chunk straight into floats.
    ByteReader reader(in, src.gzip, report);
    std::vector<unsigned char> chunk(kChunkBytes);
    const auto shortRead = [&](size_t got) {
        fail(report, "data",
             std::string(src.gzip ? "gzip stream" : where) + " ended after " + std::to_string(got) + " of " +
                 std::to_string(src.byteSkip + needed) + " bytes");
    };
    for (size_t skipped = 0; src.gzip && skipped < src.byteSkip;) {   // raw data was skipped by seeking
        const size_t want = std::min(kChunkBytes, src.byteSkip - skipped);
        const size_t got = reader.read(chunk.data(), want);
        skipped += got;
        if (got < want) shortRead(skipped);
    }
    std::vector<float> values(count);
    const size_t voxelBytes = voxelTypeBytes(type);
    for (size_t done = 0; done < needed;) {
        const size_t want = std::min(kChunkBytes, needed - done);
        const size_t got = reader.read(chunk.data(), want);
        if (got < want) shortRead(src.byteSkip + done + got);
        decodeVoxels(chunk.data(), want / voxelBytes, type, src.endian, values.data() + done / voxelBytes);
        done += want;
    }
    if (src.exact && src.gzip && reader.read(chunk.data(), 1) == 1)
        fail(report, "data", "gzip stream holds more than the expected " + expected);
    return values;
}

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

glm::dvec3 nrrdSpacing(const fs::path& path, const NrrdHeader& header) {
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
        // Volume has no direction matrix, so only each axis' step length is kept (a rotation is dropped).
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
        }
    }
    return spacing;
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

Volume loadRaw(const std::filesystem::path& path, const RawOptions& options) {
    Volume volume;
    volume.dims = checkedDims(path, "dims", options.dims.x, options.dims.y, options.dims.z);
    for (int axis = 0; axis < 3; ++axis)
        if (!std::isfinite(options.spacing[axis]) || options.spacing[axis] <= 0)
            fail(path, "spacing",
                 "axis " + std::to_string(axis) + " is " + std::to_string(options.spacing[axis]) +
                     ", expected a finite positive number");

    DataSource src{.file = path, .byteSkip = options.headerBytes, .exact = true, .endian = options.endian};
    // Compressed when named so or when it starts with the gzip magic bytes 1f 8b.
    std::ifstream probe = openFile(path, path, "");
    unsigned char magic[2] = {0, 0};
    probe.read(reinterpret_cast<char*>(magic), 2);
    src.gzip = lower(path.filename().string()).ends_with(".gz") || (magic[0] == 0x1f && magic[1] == 0x8b);

    volume.name = volumeName(path);
    volume.type = options.type;
    volume.spacing = options.spacing;
    volume.values = readVoxels(path, src, volume.dims, volume.type);
    updateRange(volume);
    return volume;
}

Volume loadNrrd(const std::filesystem::path& path) {
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
    volume.spacing = nrrdSpacing(path, header);
    if (const NrrdField* origin = header.find("spaceorigin")) {
        const auto vectors = parseVectors(path, *origin);
        if (vectors.size() != 1 || vectors[0].size() != 3)
            fail(path, origin->name, "expected one 3-vector such as (0,0,0), got " + excerpt(origin->value));
        volume.origin = {vectors[0][0], vectors[0][1], vectors[0][2]};
    }

    // 4. Storage: encoding, endianness (multi-byte types only), skips and the data's location.
    DataSource src;
    const NrrdField& encoding = require("encoding", "encoding");
    const std::string enc = lower(encoding.value);
    if (enc == "gzip" || enc == "gz")
        src.gzip = true;
    else if (enc != "raw")
        fail(path, encoding.name, excerpt(encoding.value) + " is not supported (supported: raw, gzip)");
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

Volume loadVolume(const std::filesystem::path& path, const std::optional<RawOptions>& raw) {
    std::error_code ec;
    if (!fs::exists(path, ec)) fail(path, "", "cannot open: no such file");
    const std::string name = lower(path.filename().string());
    if (name.ends_with(".nrrd") || name.ends_with(".nhdr")) return loadNrrd(path);
    if (name.ends_with(".raw") || name.ends_with(".raw.gz")) {
        const std::optional<RawOptions> options = raw ? raw : rawOptionsFromFileName(path);
        if (!options)
            fail(path, "",
                 "raw file without dims and type: give --dims and --type, or rename it like "
                 "name_256x256x128_uint8.raw (types: uint8, uint16, int16, float32)");
        return loadRaw(path, *options);
    }
    fail(path, "",
         "unknown file type " + excerpt(path.extension().string()) +
             " (supported: .nrrd, .nhdr, .raw, .raw.gz)");
}

} // namespace renderer
