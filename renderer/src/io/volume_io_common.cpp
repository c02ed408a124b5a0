// The readers' shared machinery (volume_io_detail.h): text helpers, size checks, file opening and the
// streamed voxel reader with raw, gzip/zlib and bzip2 storage.
#include "volume_io_detail.h"

#include <sys/resource.h>
#include <unistd.h>
#include <zlib.h>
#ifdef SPLATLAB_HAVE_BZIP2
#include <bzlib.h>
#endif

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <type_traits>

namespace renderer::io {

namespace {
constexpr size_t kChunkBytes = size_t(1) << 16; // read/inflate granularity; a multiple of every voxel size
// Deflate cannot expand more than 1032:1 (a 258-byte match per 2 bits); a stream that would have to
// is lying about its size, and is rejected before the voxels are allocated.
constexpr uintmax_t kMaxDeflateRatio = 1032;
} // namespace

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string_view trim(std::string_view s) {
    const auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (!s.empty() && isSpace(s.front()))
        s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back()))
        s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> splitWords(std::string_view s) {
    std::vector<std::string_view> words;
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i])))
            ++i;
        const size_t start = i;
        while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i])))
            ++i;
        if (i > start) words.push_back(s.substr(start, i - start));
    }
    return words;
}

std::string excerpt(std::string_view s) {
    std::string out = "'";
    for (char c : s.substr(0, 60))
        out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
    return out + (s.size() > 60 ? "...'" : "'");
}

std::optional<long long> parseInt(std::string_view s) {
    if (s.starts_with('+')) s.remove_prefix(1);
    long long v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
    return v;
}

std::optional<double> parseDouble(std::string_view s) {
    if (s.starts_with('+')) s.remove_prefix(1);
    double v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
    return v;
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

std::string layoutText(glm::ivec3 dims, VoxelType type) {
    return std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" + std::to_string(dims.z) + " " +
           voxelTypeName(type);
}

glm::ivec3 checkedDims(const fs::path& path, const std::string& field, long long x, long long y,
                       long long z) {
    const long long sizes[3] = {x, y, z};
    for (long long s : sizes)
        if (s <= 0) fail(path, field, "size " + std::to_string(s) + " must be a positive integer");
    const std::string text = std::to_string(x) + " x " + std::to_string(y) + " x " + std::to_string(z);
    for (long long s : sizes)
        if (s > kMaxAxisVoxels)
            fail(path, field, text + ": " + std::to_string(s) + " voxels along an axis is more than the " +
                                  std::to_string(kMaxAxisVoxels) + " SplatLab renders");
    const unsigned long long product = (unsigned long long)x * (unsigned long long)y * (unsigned long long)z;
    if (product > kMaxVoxels)
        fail(path, field, text + " = " + std::to_string(product) + " voxels is more than the " +
                              std::to_string(kMaxVoxels) + " SplatLab renders (e.g. 894^3, 1024 x 1024 x 682)");
    return {int(x), int(y), int(z)};
}

void checkVoxelsFitTheBudget(const fs::path& path, const std::string& field, const std::string& claim,
                             uint64_t voxels, VoxelType type) {
    if (const auto why = overMemoryBudget(voxels, type)) fail(path, field, claim + " voxels " + *why);
}

glm::dvec3 checkedSpacing(const fs::path& path, const std::string& field, glm::dvec3 spacing) {
    for (int axis = 0; axis < 3; ++axis)
        if (!std::isfinite(spacing[axis]) || spacing[axis] <= 0)
            fail(path, field,
                 "spacing " + number(spacing[axis]) + " on axis " + std::to_string(axis) +
                     ", expected a finite positive number");
    // Footprints, the camera and the ground truth square and divide spacings: outside this range they
    // under- or overflow and the volume renders blank (1e-320 and 1e300 did). Real scans use 1e-3..1e2
    // (metres to millimetres, microns for microscopy).
    for (int axis = 0; axis < 3; ++axis)
        if (spacing[axis] < kMinSpacing || spacing[axis] > kMaxSpacing)
            fail(path, field,
                 "spacing " + number(spacing[axis]) + " on axis " + std::to_string(axis) + ", expected " +
                     number(kMinSpacing) + " to " + number(kMaxSpacing) + " (in the file's units)");
    return spacing;
}

std::string volumeName(const fs::path& path) {
    std::string name = path.filename().string();
    for (std::string_view ext : {".gz", ".bz2"})
        if (name.size() > ext.size() && lower(name).ends_with(ext)) name.resize(name.size() - ext.size());
    for (std::string_view ext :
         {".raw", ".nrrd", ".nhdr", ".mhd", ".mha", ".nii", ".slc", ".dat", ".tiff", ".tif"})
        if (name.size() > ext.size() && lower(name).ends_with(ext)) {
            name.resize(name.size() - ext.size());
            break;
        }
    return name;
}

std::ifstream openFile(const fs::path& file, const fs::path& report, const std::string& field) {
    const std::string what = file == report ? "cannot open: " : "cannot open '" + file.string() + "': ";
    std::error_code ec;
    const fs::file_status status = fs::status(file, ec);
    if (fs::is_directory(status)) fail(report, field, what + "is a directory");
    if (fs::exists(status) && !fs::is_regular_file(status))
        fail(report, field, what + "not a regular file (devices and pipes are not read)");
    std::ifstream in(file, std::ios::binary);
    if (!in) fail(report, field, what + std::strerror(errno));
    return in;
}

uintmax_t fileSize(const fs::path& file, const fs::path& report, const std::string& field) {
    std::error_code ec;
    const uintmax_t size = fs::file_size(file, ec);
    if (ec) fail(report, field, "cannot read the size of '" + file.string() + "': " + ec.message());
    return size;
}

bool bzip2Available() {
#ifdef SPLATLAB_HAVE_BZIP2
    return true;
#else
    return false;
#endif
}

const char* compressionName(Compression c) {
    switch (c) {
    case Compression::None:
        return "raw";
    case Compression::Zlib:
        return "gzip/zlib";
    case Compression::Bzip2:
        return "bzip2";
    }
    return "unknown";
}

struct ByteReader::State {
    z_stream zs{};
#ifdef SPLATLAB_HAVE_BZIP2
    bz_stream bz{};
#endif
    bool ended = false;
    std::vector<unsigned char> buffer = std::vector<unsigned char>(kChunkBytes);
};

ByteReader::ByteReader(std::istream& in, Compression compression, fs::path report)
    : m_in(in), m_compression(compression), m_report(std::move(report)), m_state(std::make_unique<State>()) {
    // 32 + MAX_WBITS: accept a gzip (NRRD, .nii.gz) or zlib (MetaImage) wrapper, whichever is there.
    if (m_compression == Compression::Zlib && inflateInit2(&m_state->zs, 32 + MAX_WBITS) != Z_OK)
        fail(m_report, "data", "cannot start zlib");
    if (m_compression == Compression::Bzip2) {
#ifdef SPLATLAB_HAVE_BZIP2
        if (BZ2_bzDecompressInit(&m_state->bz, 0, 0) != BZ_OK) fail(m_report, "data", "cannot start bzip2");
#else
        fail(m_report, "encoding",
             "bzip2 data, but this build has no libbz2 (apt install libbz2-dev, rebuild)");
#endif
    }
}

ByteReader::~ByteReader() {
    if (m_compression == Compression::Zlib) inflateEnd(&m_state->zs);
#ifdef SPLATLAB_HAVE_BZIP2
    if (m_compression == Compression::Bzip2) BZ2_bzDecompressEnd(&m_state->bz);
#endif
}

size_t ByteReader::read(unsigned char* dst, size_t n) {
    if (m_compression == Compression::None) {
        m_in.read(reinterpret_cast<char*>(dst), std::streamsize(n));
        return size_t(m_in.gcount());
    }
    State& s = *m_state;
    size_t got = 0;
    while (got < n && !s.ended) {
        const auto refill = [&](unsigned& availIn) -> unsigned char* {
            m_in.read(reinterpret_cast<char*>(s.buffer.data()), std::streamsize(s.buffer.size()));
            availIn = unsigned(m_in.gcount());
            return s.buffer.data();
        };
        const size_t want = std::min(n - got, kChunkBytes); // avail_out is a 32-bit unsigned
        if (m_compression == Compression::Zlib) {
            z_stream& zs = s.zs;
            if (zs.avail_in == 0) {
                zs.next_in = refill(zs.avail_in);
                if (zs.avail_in == 0) break; // the file ended inside the stream: truncated
            }
            zs.next_out = dst + got;
            zs.avail_out = uInt(want);
            const int rc = inflate(&zs, Z_NO_FLUSH);
            got += want - zs.avail_out;
            if (rc == Z_STREAM_END) {
                // gzip allows concatenated members (cat a.gz b.gz); carry on when more input follows.
                if (zs.avail_in == 0 && m_in.peek() == std::char_traits<char>::eof())
                    s.ended = true;
                else
                    inflateReset(&zs);
            } else if (rc != Z_OK && rc != Z_BUF_ERROR) {
                fail(m_report, "data",
                     std::string("gzip/zlib stream is corrupt: ") + (zs.msg ? zs.msg : zError(rc)));
            }
        } else {
#ifdef SPLATLAB_HAVE_BZIP2
            bz_stream& bz = s.bz;
            if (bz.avail_in == 0) {
                bz.next_in = reinterpret_cast<char*>(refill(bz.avail_in));
                if (bz.avail_in == 0) break;
            }
            bz.next_out = reinterpret_cast<char*>(dst + got);
            bz.avail_out = unsigned(want);
            const int rc = BZ2_bzDecompress(&bz);
            got += want - bz.avail_out;
            if (rc == BZ_STREAM_END) {
                // bzip2 also concatenates streams (pbzip2 writes them); restart when input follows.
                if (bz.avail_in == 0 && m_in.peek() == std::char_traits<char>::eof()) {
                    s.ended = true;
                } else {
                    char* next = bz.next_in;
                    const unsigned avail = bz.avail_in;
                    BZ2_bzDecompressEnd(&bz);
                    bz = bz_stream{};
                    if (BZ2_bzDecompressInit(&bz, 0, 0) != BZ_OK)
                        fail(m_report, "data", "cannot restart bzip2");
                    bz.next_in = next;
                    bz.avail_in = avail;
                }
            } else if (rc != BZ_OK) {
                fail(m_report, "data", "bzip2 stream is corrupt (libbz2 error " + std::to_string(rc) + ")");
            }
#endif
        }
    }
    return got;
}

namespace {
// Stored bytes of `count` voxels of out's type, in `endian` order, into out[0..count).
template <class T> void decodeTyped(const unsigned char* bytes, size_t count, Endian endian, T* out) {
    if constexpr (sizeof(T) == 1) {
        std::memcpy(out, bytes, count);
    } else {
        using Bits = std::conditional_t<sizeof(T) == 2, uint16_t, uint32_t>;
        const bool little = endian == Endian::Little;
        for (size_t i = 0; i < count; ++i) {
            const unsigned char* b = bytes + i * sizeof(T);
            Bits bits = 0;
            for (size_t k = 0; k < sizeof(T); ++k)
                bits = Bits(bits | Bits(b[little ? k : sizeof(T) - 1 - k]) << (8 * k));
            out[i] = std::bit_cast<T>(bits);
        }
    }
}
} // namespace

void decodeVoxels(const unsigned char* bytes, size_t count, Endian endian, VoxelValues& out, size_t first) {
    out.visit([&](auto& values) { decodeTyped(bytes, count, endian, values.data() + first); });
}

void reportProgress(const ProgressCallback& progress, double fraction, const fs::path& report) {
    if (progress && !progress(fraction)) throw Cancelled(report.string() + ": reading cancelled");
}

VoxelValues readVoxels(const fs::path& report, const DataSource& src, glm::ivec3 dims, VoxelType type) {
    const size_t count = size_t(dims.x) * size_t(dims.y) * size_t(dims.z); // checkedDims() bounded it
    const size_t needed = count * voxelTypeBytes(type);
    checkVoxelsFitTheBudget(report, src.sizeField, std::to_string(dims.x) + " x " + std::to_string(dims.y) + " x " +
                            std::to_string(dims.z), count, type);
    const bool compressed = src.compression != Compression::None;
    const std::string where = src.file == report ? "file" : "data file '" + src.file.string() + "'";
    // With a byte skip the file must hold the skip and then the data: the total is what is compared.
    const std::string expected =
        src.byteSkip ? std::to_string(src.byteSkip + needed) + " bytes (a " + std::to_string(src.byteSkip) +
                           "-byte skip, then " + std::to_string(needed) + " bytes of " + layoutText(dims, type) + ")"
                     : std::to_string(needed) + " bytes (" + layoutText(dims, type) + ")";
    const std::string streamName = std::string(compressionName(src.compression)) + " stream";

    // 1. Open and find where the stored data starts (after the header and any skipped lines).
    std::ifstream in = openFile(src.file, report, src.file == report ? "" : "data file");
    const uintmax_t size = fileSize(src.file, report, "data");
    if (src.offset < 0 || uintmax_t(src.offset) > size)
        fail(report, "data",
             where + " has " + std::to_string(size) + " bytes, the data should start at byte " +
                 std::to_string(src.offset));
    in.seekg(src.offset);
    for (size_t line = 0; line < src.lineSkip; ++line) {
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
        if (!in)
            fail(report, "line skip", where + " has fewer than " + std::to_string(src.lineSkip) + " lines");
    }
    const std::streamoff start = in.tellg();
    if (start < 0) fail(report, "data", "cannot seek in " + where);
    const uintmax_t available = size - uintmax_t(start);

    // 2. Compare the file size with what the header promises before allocating: exactly for raw
    //    data, by the format's largest expansion for deflate (bzip2 has no useful bound).
    if (!compressed) {
        const std::string after = start > 0 ? " after the header" : "";
        if (available < src.byteSkip || available - src.byteSkip < needed)
            fail(report, "data",
                 where + " has " + std::to_string(available) + " bytes" + after + ", expected " + expected);
        // Headers that tolerate trailing bytes (a writer's newline) still refuse a whole slice more: the
        // header's sizes are then wrong, and the volume read would be a wrong cut of the data.
        const size_t trailing = available - src.byteSkip - needed;
        if (trailing > 0 && (src.exact || trailing >= needed / size_t(dims.z)))
            fail(report, "data",
                 where + " has " + std::to_string(available) + " bytes" + after + ", expected " + expected +
                     "; " + std::to_string(trailing) + " trailing bytes" +
                     (src.exact ? "" : ", a slice or more: do the sizes in the header match the data?"));
        in.seekg(std::streamoff(src.byteSkip), std::ios::cur);
    } else if (src.compression == Compression::Zlib &&
               available * kMaxDeflateRatio + 64 < src.byteSkip + needed) {
        fail(report, "data",
             "a " + std::to_string(available) + "-byte gzip/zlib stream cannot hold " + expected +
                 " (deflate expands at most 1032:1)");
    }

    // 3. Stream the data in chunks: drop the byte skip, then decode each chunk straight into floats.
    ByteReader reader(in, src.compression, report);
    std::vector<unsigned char> chunk(kChunkBytes);
    const auto shortRead = [&](size_t got) {
        fail(report, "data",
             (compressed ? streamName : where) + " ended after " + std::to_string(got) + " of " +
                 std::to_string(src.byteSkip + needed) + " bytes");
    };
    for (size_t skipped = 0; compressed && skipped < src.byteSkip;) { // raw data was skipped by seeking
        const size_t want = std::min(kChunkBytes, src.byteSkip - skipped);
        const size_t got = reader.read(chunk.data(), want);
        skipped += got;
        if (got < want) shortRead(skipped);
    }
    // Compressed data: reserve for up to 64:1 (CT and MRI compress far less), grow beyond that as the
    // bytes arrive, so a small stream that lies about its size never costs gigabytes. The voxels keep
    // the file's type (voxel_values.h).
    const size_t voxelBytes = voxelTypeBytes(type);
    VoxelValues out = VoxelValues::zeros(type, compressed ? 0 : count);
    out.visit([&](auto& values) {
        if (compressed) values.reserve(size_t(std::min<uintmax_t>(count, available * 64 / voxelBytes + kChunkBytes)));
        for (size_t done = 0; done < needed;) {
            const size_t want = std::min(kChunkBytes, needed - done);
            const size_t got = reader.read(chunk.data(), want);
            if (got < want) shortRead(src.byteSkip + done + got);
            if (values.size() < (done + want) / voxelBytes) values.resize((done + want) / voxelBytes);
            decodeTyped(chunk.data(), want / voxelBytes, src.endian, values.data() + done / voxelBytes);
            done += want;
            reportProgress(src.progress, double(done) / double(needed), report);
        }
    });
    if (src.exact && compressed && reader.read(chunk.data(), 1) == 1)
        fail(report, "data", streamName + " holds more than the expected " + expected);
    return out;
}

std::string readSmallFile(const fs::path& path, size_t maxBytes) {
    std::ifstream in = openFile(path, path, "");
    const uintmax_t size = fileSize(path, path, "");
    if (size > maxBytes)
        fail(path, "",
             "file has " + std::to_string(size) + " bytes, more than the " + std::to_string(maxBytes) +
                 " this format can hold");
    std::string bytes(size_t(size), '\0');
    in.read(bytes.data(), std::streamsize(size));
    if (size_t(in.gcount()) != bytes.size()) fail(path, "", "read ended early");
    return bytes;
}

} // namespace renderer::io

namespace renderer {

uint64_t volumeMemoryBudget() {
    if (const char* set = std::getenv("SPLATLAB_MEMORY_BUDGET_MB")) {
        char* end = nullptr;
        const unsigned long long mib = std::strtoull(set, &end, 10);
        if (end != set && *end == '\0' && mib > 0 && mib < (1ull << 40)) return uint64_t(mib) * io::kMiB;
    }
    // Physical memory, or less where a limit on this process says so (ulimit -v, -d).
    uint64_t usable = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGESIZE));
    for (int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit limit{};
        if (getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
            usable = std::min<uint64_t>(usable, uint64_t(limit.rlim_cur));
    }
    return usable / 2;
}

std::optional<std::string> overMemoryBudget(uint64_t voxels, VoxelType type) {
    const uint64_t bytes = voxels * voxelTypeBytes(type), budget = volumeMemoryBudget();
    if (bytes <= budget) return std::nullopt;
    return "need " + std::to_string((bytes + io::kMiB - 1) / io::kMiB) + " MiB as " + voxelTypeName(type) +
           ", more than the memory budget of " + std::to_string(budget / io::kMiB) +
           " MiB (half of what this process may use; SPLATLAB_MEMORY_BUDGET_MB sets it)";
}

} // namespace renderer
