// NIfTI-1 single files (.nii, .nii.gz): the 348-byte binary header in either byte order (told by
// sizeof_hdr), voxels from vox_offset. pixdim gives the spacing, scl_slope/scl_inter the data units,
// the sform (else the qform) the origin and axis directions. NIfTI-2 and .hdr/.img pairs are refused.
#include "renderer/io/volume_io.h"

#include "volume_io_detail.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace renderer {

namespace {

using namespace io;

// How far above 1 the squares of a stored unit quaternion may round (float32 parts).
constexpr double kQuaternionSlack = 1e-5;

constexpr size_t kHeaderBytes = 348;

// Fixed-offset reads from the header in the file's byte order.
struct NiftiHeader {
    unsigned char bytes[kHeaderBytes];
    bool big = false;

    uint32_t u32(size_t at) const {
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i)
            v |= uint32_t(bytes[at + size_t(i)]) << (big ? 8 * (3 - i) : 8 * i);
        return v;
    }
    int16_t i16(size_t at) const {
        return int16_t(uint16_t(big ? bytes[at] << 8 | bytes[at + 1] : bytes[at + 1] << 8 | bytes[at]));
    }
    int32_t i32(size_t at) const { return int32_t(u32(at)); }
    double f32(size_t at) const { return double(std::bit_cast<float>(u32(at))); }
};

struct NiftiType {
    int code;
    const char* name;
    std::optional<VoxelType> type;
};
const NiftiType kNiftiTypes[] = {
    {2, "uint8", VoxelType::U8},        {4, "int16", VoxelType::I16},     {16, "float32", VoxelType::F32},
    {512, "uint16", VoxelType::U16},    {1, "binary", std::nullopt},      {8, "int32", std::nullopt},
    {32, "complex64", std::nullopt},    {64, "float64", std::nullopt},    {128, "rgb24", std::nullopt},
    {256, "int8", std::nullopt},        {768, "uint32", std::nullopt},    {1024, "int64", std::nullopt},
    {1280, "uint64", std::nullopt},     {1536, "float128", std::nullopt}, {1792, "complex128", std::nullopt},
    {2048, "complex256", std::nullopt}, {2304, "rgba32", std::nullopt},
};

// The stored values (finite ones within `stored`) times slope plus inter. Whole slopes and intercepts
// that keep integers within int16 (a CT's 0..4095 with an intercept of -1024) stay 2 bytes a voxel;
// anything else becomes 32-bit floats.
VoxelValues scaledValues(const VoxelValues& values, double slope, double inter, ValueRange stored) {
    const bool whole = values.type() != VoxelType::F32 && slope == std::round(slope) && inter == std::round(inter);
    const double a = double(stored.lo) * slope + inter, b = double(stored.hi) * slope + inter;
    constexpr double lowest = std::numeric_limits<int16_t>::min(), highest = std::numeric_limits<int16_t>::max();
    return values.visit([&](const auto& in) -> VoxelValues {
        if (whole && std::min(a, b) >= lowest && std::max(a, b) <= highest) {
            std::vector<int16_t> out(in.size());
            for (size_t i = 0; i < in.size(); ++i) out[i] = int16_t(std::lround(double(in[i]) * slope + inter));
            return out;
        }
        std::vector<float> out(in.size());
        for (size_t i = 0; i < in.size(); ++i) out[i] = float(double(in[i]) * slope + inter);
        return out;
    });
}

} // namespace

Volume loadNifti(const std::filesystem::path& path, const ProgressCallback& progress) {
    // 1. The header, through zlib when the file is gzip-compressed (by name or by its 1f 8b magic).
    std::ifstream in = openFile(path, path, "");
    unsigned char magic[2] = {0, 0};
    in.read(reinterpret_cast<char*>(magic), 2);
    in.clear();
    in.seekg(0);
    const bool gzip =
        lower(path.filename().string()).ends_with(".gz") || (magic[0] == 0x1f && magic[1] == 0x8b);
    NiftiHeader h{};
    {
        ByteReader reader(in, gzip ? Compression::Zlib : Compression::None, path);
        const size_t got = reader.read(h.bytes, kHeaderBytes);
        if (got < kHeaderBytes)
            fail(path, "sizeof_hdr",
                 std::string(gzip ? "gzip stream" : "file") + " has " + std::to_string(got) +
                     " bytes, expected a 348-byte NIfTI-1 header");
    }

    // 2. Byte order: sizeof_hdr is 348 in the file's own order.
    h.big = false;
    if (h.i32(0) != 348) {
        h.big = true;
        if (h.i32(0) != 348) {
            h.big = false;
            const int32_t v = h.i32(0);
            fail(path, "sizeof_hdr",
                 std::to_string(v) + (v == 540 ? " (NIfTI-2, not supported)" : "") +
                     ", expected 348 in either byte order (NIfTI-1)");
        }
    }
    const std::string magicText(reinterpret_cast<const char*>(h.bytes + 344), 4);
    if (magicText == std::string("ni1\0", 4))
        fail(path, "magic", "'ni1' (a .hdr/.img pair) is not supported; convert to a single .nii file");
    if (magicText != std::string("n+1\0", 4))
        fail(path, "magic", excerpt(magicText) + ", expected 'n+1' (NIfTI-1 single file)");

    // 3. Dims: dim[0] axes, of which the fourth and later must be 1.
    const int16_t rank = h.i16(40);
    if (rank < 3 || rank > 7)
        fail(path, "dim[0]", std::to_string(rank) + ", expected 3 (a 3D volume; 4..7 with size 1 beyond z)");
    long long dim[8];
    for (int i = 0; i < 8; ++i)
        dim[i] = h.i16(size_t(40 + 2 * i));
    for (int i = 4; i <= rank; ++i)
        if (dim[i] != 1)
            fail(path, "dim[" + std::to_string(i) + "]",
                 std::to_string(dim[i]) + ", expected 1 (time series and vectors are not supported)");
    Volume volume;
    volume.name = volumeName(path);
    volume.dims = checkedDims(path, "dim", dim[1], dim[2], dim[3]);

    // 4. Voxel type and its bit count.
    const int16_t datatype = h.i16(70);
    const auto* t = std::find_if(std::begin(kNiftiTypes), std::end(kNiftiTypes),
                                 [&](const NiftiType& n) { return n.code == datatype; });
    if (t == std::end(kNiftiTypes) || !t->type)
        fail(path, "datatype",
             std::to_string(datatype) +
                 (t != std::end(kNiftiTypes) ? std::string(" (") + t->name + ")" : "") +
                 " is not supported (supported: 2 uint8, 4 int16, 512 uint16, 16 float32)");
    volume.type = *t->type;
    const int16_t bitpix = h.i16(72);
    if (size_t(bitpix) != voxelTypeBytes(volume.type) * 8)
        fail(path, "bitpix",
             std::to_string(bitpix) + ", expected " + std::to_string(voxelTypeBytes(volume.type) * 8) +
                 " for " + t->name);

    // 5. Spacing, data offset and scaling.
    volume.spacing = checkedSpacing(path, "pixdim", {h.f32(80), h.f32(84), h.f32(88)});
    const double voxOffset = h.f32(108);
    if (!std::isfinite(voxOffset) || voxOffset < double(kHeaderBytes) || voxOffset != std::floor(voxOffset) ||
        voxOffset > 1e9)
        fail(path, "vox_offset", number(voxOffset) + ", expected a whole number of bytes >= 348");
    const double slope = h.f32(112), inter = h.f32(116);
    if (!std::isfinite(slope))
        fail(path, "scl_slope", number(slope) + ", expected a finite number (0: none)");
    if (slope != 0 && !std::isfinite(inter))
        fail(path, "scl_inter", number(inter) + ", expected a finite number");

    // 6. Orientation (metadata): sform rows when sform_code > 0, else the qform quaternion.
    const int16_t qformCode = h.i16(252), sformCode = h.i16(254);
    if (sformCode > 0) {
        glm::dmat3 m;
        for (int row = 0; row < 3; ++row) {
            for (int col = 0; col < 3; ++col)
                m[col][row] = h.f32(size_t(280 + 16 * row + 4 * col));
            volume.origin[row] = h.f32(size_t(280 + 16 * row + 12));
        }
        for (int col = 0; col < 3; ++col) {
            const double length = glm::length(m[col]);
            if (!(length > 0) || !std::isfinite(length))
                fail(path, "srow_x/y/z",
                     "column " + std::to_string(col) + " has length " + number(length) +
                         ", expected a non-degenerate affine");
            volume.directions[col] = m[col] / length;
        }
        if (!std::isfinite(volume.origin.x + volume.origin.y + volume.origin.z))
            fail(path, "srow_x/y/z", "offset is not finite");
    } else if (qformCode > 0) {
        const double b = h.f32(256), c = h.f32(260), d = h.f32(264);
        const glm::dvec3 offset{h.f32(268), h.f32(272), h.f32(276)};
        if (!std::isfinite(b + c + d) || !std::isfinite(offset.x + offset.y + offset.z))
            fail(path, "quatern_b/c/d", "not finite");
        // (b, c, d) are a unit quaternion's last three parts, so b^2 + c^2 + d^2 <= 1; taken as they are,
        // a larger sum gives axes that are not orthonormal (a distorted volume). Float rounding of a unit
        // quaternion stays within kQuaternionSlack and is normalised away.
        double bb = b, cc = c, dd = d;
        const double squares = b * b + c * c + d * d;
        if (squares > 1.0 + kQuaternionSlack)
            fail(path, "quatern_b/c/d",
                 "b^2 + c^2 + d^2 = " + number(squares) + ", expected at most 1 (the parts of a unit quaternion)");
        if (squares > 1.0) {
            const double norm = std::sqrt(squares);
            bb /= norm, cc /= norm, dd /= norm;
        }
        const double a = std::sqrt(std::max(0.0, 1.0 - (bb * bb + cc * cc + dd * dd)));
        const double qfac = h.f32(76) < 0 ? -1.0 : 1.0; // pixdim[0]
        // Rotation from the unit quaternion (a, b, c, d), rows as in nifti1.h; z flipped by qfac.
        const glm::dmat3 r(
            glm::dvec3(a * a + bb * bb - cc * cc - dd * dd, 2 * (bb * cc + a * dd), 2 * (bb * dd - a * cc)),
            glm::dvec3(2 * (bb * cc - a * dd), a * a + cc * cc - bb * bb - dd * dd, 2 * (cc * dd + a * bb)),
            glm::dvec3(qfac * 2 * (bb * dd + a * cc), qfac * 2 * (cc * dd - a * bb),
                       qfac * (a * a + dd * dd - cc * cc - bb * bb)));
        volume.directions = r;
        volume.origin = offset;
    }

    // 7. Voxels after vox_offset (decompressed bytes for .nii.gz), then the data units.
    DataSource src{.file = path,
                   .byteSkip = size_t(voxOffset),
                   .endian = h.big ? Endian::Big : Endian::Little,
                   .sizeField = "dim",
                   .progress = progress};
    if (gzip) src.compression = Compression::Zlib;
    volume.values = readVoxels(path, src, volume.dims, volume.type);
    if (slope != 0 && !(slope == 1 && inter == 0)) {
        // Scaled values must stay 32-bit floats: a slope of 3e38 turned voxels into +inf, which then
        // vanished from the image without a word.
        updateRange(volume);   // of the stored values
        for (const double stored : {double(volume.range.lo), double(volume.range.hi)}) {
            const double scaled = stored * slope + inter;
            if (!(std::abs(scaled) <= double(std::numeric_limits<float>::max())))
                fail(path, "scl_slope",
                     "scl_slope " + number(slope) + " and scl_inter " + number(inter) + " take the stored value " +
                         number(stored) + " to " + number(scaled) +
                         ", expected scaled values within a 32-bit float's range (+-3.4e38)");
        }
        volume.values = scaledValues(volume.values, slope, inter, volume.range);
    }
    updateRange(volume);
    return volume;
}

} // namespace renderer
