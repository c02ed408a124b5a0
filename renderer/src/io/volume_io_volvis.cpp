// The classic volume-visualisation formats: VolVis .slc (a text header, an RGB icon, then 8-bit
// slices stored raw or run-length encoded) and .dat (three little-endian uint16 dims, then uint16
// voxels, as the TU Wien / volvis.org CT datasets ship). Both are read whole into memory: they are small.
#include "renderer/io/volume_io.h"

#include "volume_io_detail.h"

#include <charconv>
#include <cmath>
#include <cstring>

namespace renderer {
namespace {

using namespace io;

// The largest SLC file read: every voxel stored raw, plus a generous icon.
constexpr size_t kMaxSlcBytes = kMaxVoxels + (size_t(1) << 26);
// A run of up to 127 equal voxels costs 2 bytes, so RLE expands at most 63.5:1.
constexpr size_t kMaxRleRatio = 64;

// Reads the whitespace-separated text fields of an SLC header (fscanf-like, but bounded).
class SlcCursor {
  public:
    SlcCursor(const fs::path& path, std::string_view bytes) : m_path(path), m_bytes(bytes) {}

    long long integer(const std::string& field) {
        skipSpace();
        const size_t start = m_pos;
        long long v = 0;
        const auto [end, ec] = std::from_chars(m_bytes.data() + m_pos, m_bytes.data() + m_bytes.size(), v);
        if (ec != std::errc())
            fail(m_path, field,
                 "expected an integer at byte " + std::to_string(start) + ", got " + excerpt(token()));
        m_pos = size_t(end - m_bytes.data());
        return v;
    }
    double real(const std::string& field) {
        skipSpace();
        const size_t start = m_pos;
        double v = 0;
        const auto [end, ec] = std::from_chars(m_bytes.data() + m_pos, m_bytes.data() + m_bytes.size(), v);
        if (ec != std::errc())
            fail(m_path, field,
                 "expected a number at byte " + std::to_string(start) + ", got " + excerpt(token()));
        m_pos = size_t(end - m_bytes.data());
        return v;
    }
    // The 'X' that ends the icon size and each slice size; the binary data starts right after it.
    void marker(const std::string& field) {
        skipSpace();
        if (m_pos >= m_bytes.size() || m_bytes[m_pos] != 'X')
            fail(m_path, field,
                 "expected 'X' at byte " + std::to_string(m_pos) + ", got " + excerpt(token()));
        ++m_pos;
    }
    // The next n bytes of binary data, or a LoadError naming `field`.
    std::string_view take(size_t n, const std::string& field) {
        if (n > m_bytes.size() - m_pos)
            fail(m_path, field,
                 "needs " + std::to_string(n) + " bytes at byte " + std::to_string(m_pos) +
                     ", the file has " + std::to_string(m_bytes.size() - m_pos) + " left");
        const std::string_view out = m_bytes.substr(m_pos, n);
        m_pos += n;
        return out;
    }
    size_t left() const { return m_bytes.size() - m_pos; }

  private:
    void skipSpace() {
        while (m_pos < m_bytes.size() && std::strchr(" \t\r\n\f\v", m_bytes[m_pos]) && m_bytes[m_pos] != '\0')
            ++m_pos;
    }
    std::string_view token() const {
        return m_bytes.substr(m_pos, std::min<size_t>(12, m_bytes.size() - m_pos));
    }

    const fs::path& m_path;
    std::string_view m_bytes;
    size_t m_pos = 0;
};

// One RLE slice: a byte n | 0x80 copies the next n bytes, a byte n < 0x80 repeats the next byte n
// times, 0 ends the slice. Exactly `out.size()` voxels must come out.
void decodeSlcSlice(const fs::path& path, int z, std::string_view in, uint8_t* out, size_t plane) {
    size_t i = 0, o = 0;
    const std::string field = "slice " + std::to_string(z);
    while (i < in.size()) {
        const unsigned char head = static_cast<unsigned char>(in[i++]);
        const size_t run = head & 0x7f;
        if (run == 0) break;
        if (run > plane - o)
            fail(path, field,
                 "run-length data decodes to more than the " + std::to_string(plane) + " voxels of a slice");
        if (head & 0x80) {
            if (run > in.size() - i)
                fail(path, field,
                     "a literal run of " + std::to_string(run) + " bytes passes the end of the slice data");
            for (size_t k = 0; k < run; ++k)
                out[o++] = static_cast<uint8_t>(in[i++]);
        } else {
            if (i >= in.size()) fail(path, field, "a repeat run has no value byte");
            const uint8_t v = static_cast<uint8_t>(in[i++]);
            for (size_t k = 0; k < run; ++k)
                out[o++] = v;
        }
    }
    if (o != plane)
        fail(path, field,
             "run-length data decodes to " + std::to_string(o) + " voxels, expected " +
                 std::to_string(plane));
}

} // namespace

Volume loadSlc(const std::filesystem::path& path, const ProgressCallback& progress) {
    const std::string bytes = readSmallFile(path, kMaxSlcBytes);
    SlcCursor in(path, bytes);

    // 1. Magic, sizes, bits, spacing, units and compression.
    const long long magic = in.integer("magic");
    if (magic != 11111) fail(path, "magic", std::to_string(magic) + ", expected 11111 (VolVis SLC)");
    const long long x = in.integer("xsize"), y = in.integer("ysize"), z = in.integer("zsize");
    const long long bits = in.integer("bits_per_voxel");
    Volume volume;
    volume.name = volumeName(path);
    volume.type = VoxelType::U8;
    volume.dims = checkedDims(path, "xsize/ysize/zsize", x, y, z);
    checkVoxelsFitTheBudget(path, "xsize/ysize/zsize", layoutText(volume.dims, volume.type), volume.voxelCount(),
                            volume.type);
    if (bits != 8)
        fail(path, "bits_per_voxel", std::to_string(bits) + ", expected 8 (the only depth SLC defines)");
    glm::dvec3 spacing;
    for (int axis = 0; axis < 3; ++axis)
        spacing[axis] = in.real("x/y/z_unit");
    volume.spacing = checkedSpacing(path, "x/y/z_unit", spacing);
    in.integer("unit_type");
    in.integer("data_origin");
    in.integer("data_modification");
    const long long compression = in.integer("data_compression");
    if (compression != 0 && compression != 1)
        fail(path, "data_compression", std::to_string(compression) + ", expected 0 (none) or 1 (run-length)");

    // 2. The icon: width x height bytes per colour channel (red, green, blue); skipped.
    const long long iconW = in.integer("icon_width"), iconH = in.integer("icon_height");
    if (iconW < 0 || iconH < 0 || iconW > 65536 || iconH > 65536)
        fail(path, "icon size",
             std::to_string(iconW) + " x " + std::to_string(iconH) + ", expected 0..65536 each");
    in.marker("icon size");
    in.take(size_t(iconW) * size_t(iconH) * 3, "icon");

    // 3. Slices: "<bytes> X" then the data. The file must be able to hold the volume before it is allocated.
    const size_t plane = size_t(volume.dims.x) * size_t(volume.dims.y);
    if (in.left() * (compression ? kMaxRleRatio : 1) < volume.voxelCount())
        fail(path, "data",
             std::to_string(in.left()) + " bytes after the icon cannot hold " +
                 layoutText(volume.dims, volume.type) + (compression ? " run-length encoded" : ""));
    std::vector<uint8_t> values(volume.voxelCount());
    for (int slice = 0; slice < volume.dims.z; ++slice) {
        const std::string field = "slice " + std::to_string(slice);
        const long long size = in.integer(field + " size");
        if (size < 0) fail(path, field + " size", std::to_string(size) + ", expected a byte count");
        in.marker(field + " size");
        const std::string_view data = in.take(size_t(size), field);
        uint8_t* out = values.data() + plane * size_t(slice);
        if (compression) {
            decodeSlcSlice(path, slice, data, out, plane);
        } else {
            if (size_t(size) != plane)
                fail(path, field + " size",
                     std::to_string(size) + ", expected " + std::to_string(plane) + " (uncompressed)");
            for (size_t i = 0; i < plane; ++i)
                out[i] = static_cast<uint8_t>(data[i]);
        }
        reportProgress(progress, double(slice + 1) / double(volume.dims.z), path);
    }
    volume.values = std::move(values);
    updateRange(volume);
    return volume;
}

Volume loadDat(const std::filesystem::path& path, const ProgressCallback& progress) {
    // 1. Three little-endian uint16 sizes, x first.
    std::ifstream in = openFile(path, path, "");
    unsigned char header[6];
    in.read(reinterpret_cast<char*>(header), 6);
    if (in.gcount() != 6)
        fail(path, "dims",
             "file has " + std::to_string(in.gcount()) + " bytes, expected a 6-byte header (3 x uint16)");
    const auto u16 = [&](int i) { return (long long)(header[2 * i] | header[2 * i + 1] << 8); };
    Volume volume;
    volume.name = volumeName(path);
    volume.type = VoxelType::U16;
    volume.dims = checkedDims(path, "dims", u16(0), u16(1), u16(2));
    // 2. uint16 voxels, exactly filling the rest of the file.
    DataSource src{.file = path, .offset = 6, .exact = true, .endian = Endian::Little,
                   .sizeField = "dims", .progress = progress};
    volume.values = readVoxels(path, src, volume.dims, volume.type);
    updateRange(volume);
    return volume;
}

} // namespace renderer
