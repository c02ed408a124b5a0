// The formats beyond raw and NRRD: MetaImage, NIfTI-1, VolVis .slc, .dat, image stacks, NRRD bzip2.
// Round trips are written by the tests; the real originals in ../shared are compared with their raw
// copies (skipped when ../shared is absent); malformed files must each give a LoadError naming the file,
// the field and what was expected.
#include "renderer/errors.h"
#include "renderer/io/volume_io.h"
#include "test_paths.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

using namespace renderer;
namespace fs = std::filesystem;

namespace {

fs::path outDir() { return testing_support::testOutputDir("volume_formats"); }

void writeFile(const fs::path& path, const std::string& bytes) {
    ASSERT_TRUE(testing_support::writeFile(path, bytes)) << "cannot write " << path;
}

// In-memory deflate with a gzip (windowBits 16 + 15) or zlib (15) wrapper.
std::string deflateBytes(const std::string& bytes, bool gzip) {
    z_stream zs{};
    EXPECT_EQ(deflateInit2(&zs, 6, Z_DEFLATED, gzip ? 16 + MAX_WBITS : MAX_WBITS, 8, Z_DEFAULT_STRATEGY),
              Z_OK);
    std::string out(deflateBound(&zs, uLong(bytes.size())) + 32, '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    zs.avail_in = uInt(bytes.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = uInt(out.size());
    EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}
std::string gzipBytes(const std::string& b) { return deflateBytes(b, true); }
std::string zlibBytes(const std::string& b) { return deflateBytes(b, false); }

std::string rampBytes(size_t n) {
    std::string s(n, '\0');
    for (size_t i = 0; i < n; ++i)
        s[i] = char(i * 7 % 251);
    return s;
}

template <class T> std::string bytesOf(const std::vector<T>& values, bool bigEndian) {
    std::string out;
    for (T v : values) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (bigEndian) std::reverse(b, b + sizeof(T));
        out.append(b, sizeof(T));
    }
    return out;
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
    if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

void expectLoadError(const fs::path& path, const std::vector<std::string>& expect) {
    try {
        loadVolume(path);
        ADD_FAILURE() << "expected LoadError for " << path;
    } catch (const LoadError& e) {
        const std::string msg = e.what();
        EXPECT_TRUE(contains(msg, path.string() + ": "));
        for (const std::string& part : expect)
            EXPECT_TRUE(contains(msg, part));
    }
}

// CRC-32 of the voxel values as float bits: a checksum that sees every voxel and its exact value.
uint32_t voxelChecksum(const Volume& v) {
    std::vector<float> values(v.values.size());
    for (size_t i = 0; i < values.size(); ++i) values[i] = v.values[i];
    return uint32_t(crc32(0, reinterpret_cast<const Bytef*>(values.data()), uInt(values.size() * sizeof(float))));
}

// == Writers for the binary formats

// A NIfTI-1 header (348 bytes) in either byte order; fields not given are zero.
struct NiftiFields {
    bool big = false;
    int32_t sizeofHdr = 348;
    std::vector<int16_t> dim = {3, 4, 3, 2, 1, 1, 1, 1};
    int16_t datatype = 4, bitpix = 16; // int16
    std::vector<float> pixdim = {1, 1.5f, 2, 2.5f, 1, 1, 1, 1};
    float voxOffset = 352, slope = 0, inter = 0;
    int16_t qformCode = 0, sformCode = 0;
    std::vector<float> quatern = {0, 0, 0, 0, 0, 0}; // b, c, d, qoffset x, y, z
    std::vector<float> srow = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    std::string magic = std::string("n+1\0", 4);
};

std::string niftiHeader(const NiftiFields& f) {
    std::string h(348, '\0');
    const auto put = [&](size_t at, auto value) {
        char b[sizeof(value)];
        std::memcpy(b, &value, sizeof(value));
        if (f.big) std::reverse(b, b + sizeof(value));
        std::memcpy(&h[at], b, sizeof(value));
    };
    put(0, f.sizeofHdr);
    for (size_t i = 0; i < 8; ++i)
        put(40 + 2 * i, f.dim[i]);
    put(70, f.datatype);
    put(72, f.bitpix);
    for (size_t i = 0; i < 8; ++i)
        put(76 + 4 * i, f.pixdim[i]);
    put(108, f.voxOffset);
    put(112, f.slope);
    put(116, f.inter);
    put(252, f.qformCode);
    put(254, f.sformCode);
    for (size_t i = 0; i < 6; ++i)
        put(256 + 4 * i, f.quatern[i]);
    for (size_t i = 0; i < 12; ++i)
        put(280 + 4 * i, f.srow[i]);
    std::memcpy(&h[344], f.magic.data(), 4);
    return h;
}

// The 4-byte extension flag and padding up to vox_offset, then the data.
std::string niftiFile(const NiftiFields& f, const std::string& data) {
    std::string s = niftiHeader(f);
    const size_t offset =
        std::isfinite(f.voxOffset) && f.voxOffset >= 348 && f.voxOffset < 1e6 ? size_t(f.voxOffset) : 352;
    s.resize(offset, '\0');
    return s + data;
}

// An SLC file: text header, a w x h RGB icon, then each slice as "<bytes> X<bytes>".
std::string slcFile(glm::ivec3 dims, int compression, const std::vector<std::string>& slices,
                    const std::string& units = "1.000000 1.000000 2.000000", int bits = 8) {
    std::string s = "11111\n" + std::to_string(dims.x) + " " + std::to_string(dims.y) + " " +
                    std::to_string(dims.z) + " " + std::to_string(bits) + "\n" + units + "\n1 6 0 " +
                    std::to_string(compression) + "\n2 2 X";
    s += std::string(2 * 2 * 3, '\x7f');
    for (const std::string& slice : slices)
        s += std::to_string(slice.size()) + " X" + slice;
    return s;
}

std::string datFile(uint16_t x, uint16_t y, uint16_t z, const std::string& voxels) {
    return bytesOf(std::vector<uint16_t>{x, y, z}, false) + voxels;
}

// == MetaImage

TEST(MetaImageLoad, LocalBigEndianUint16WithGeometry) {
    const std::vector<uint16_t> values = {0, 1, 2, 300, 40000, 65535, 7, 8, 9, 10, 11, 12};
    writeFile(outDir() / "local_u16.mha",
              "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = True\n"
              "TransformMatrix = 1 0 0 0 -1 0 0 0 -1\nOffset = 1.5 360 -2\nElementSpacing = 0.5 1 2.5\n"
              "DimSize = 3 2 2\nElementType = MET_USHORT\nElementDataFile = LOCAL\n" +
                  bytesOf(values, true));
    const Volume v = loadVolume(outDir() / "local_u16.mha");
    EXPECT_EQ(v.name, "local_u16");
    EXPECT_EQ(v.dims, glm::ivec3(3, 2, 2));
    EXPECT_EQ(v.type, VoxelType::U16);
    EXPECT_EQ(v.spacing, glm::dvec3(0.5, 1, 2.5));
    EXPECT_EQ(v.origin, glm::dvec3(1.5, 360, -2));
    EXPECT_EQ(v.directions, glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1)));
    ASSERT_EQ(v.values.size(), values.size());
    for (size_t i = 0; i < values.size(); ++i)
        EXPECT_EQ(v.values[i], float(values[i]));
    EXPECT_EQ(v.range.hi, 65535.0f);
}

TEST(MetaImageLoad, ZlibCompressedHounsfieldInt16KeepsNegativeValues) {
    const std::vector<int16_t> hu = {-1024, -1000, -500, 0, 40, 400, 1000, 3071};
    const std::string z = zlibBytes(bytesOf(hu, false));
    writeFile(outDir() / "ct_zlib.mha",
              "NDims = 3\nDimSize = 2 2 2\nElementType = MET_SHORT\nCompressedData = True\n"
              "CompressedDataSize = " +
                  std::to_string(z.size()) + "\nElementDataFile = LOCAL\n" + z);
    const Volume v = loadVolume(outDir() / "ct_zlib.mha");
    EXPECT_EQ(v.type, VoxelType::I16);
    for (size_t i = 0; i < hu.size(); ++i)
        EXPECT_EQ(v.values[i], float(hu[i]));
    EXPECT_EQ(v.range.lo, -1024.0f);
    EXPECT_EQ(v.range.hi, 3071.0f);
}

TEST(MetaImageLoad, DetachedDataWithHeaderSizeAndElementSize) {
    const std::vector<float> values = {0.5f, -1.25f, 3, 4, 5, 6, 7, 1e6f};
    writeFile(outDir() / "detached_f32.bin", "16 bytes of junk" + bytesOf(values, false));
    writeFile(outDir() / "detached_f32.mhd",
              "NDims = 3\nDimSize = 2 2 2\nElementSize = 2 2 2\nElementType = MET_FLOAT\n"
              "HeaderSize = 16\nElementDataFile = detached_f32.bin\n");
    const Volume v = loadVolume(outDir() / "detached_f32.mhd");
    EXPECT_EQ(v.spacing, glm::dvec3(2.0));
    for (size_t i = 0; i < values.size(); ++i)
        EXPECT_EQ(v.values[i], values[i]);
    // HeaderSize = -1: the voxels are the file's last bytes.
    writeFile(outDir() / "tail_f32.mhd",
              "NDims = 3\nDimSize = 2 2 2\nElementType = MET_FLOAT\nHeaderSize = -1\n"
              "ElementDataFile = detached_f32.bin\n");
    EXPECT_EQ(loadVolume(outDir() / "tail_f32.mhd").values, v.values);
}

// == NIfTI-1

TEST(NiftiLoad, BothByteOrdersWithScalingAndVoxOffset) {
    const std::vector<int16_t> raw = {-2, -1, 0,  1,  2,  3,  4,  5,  6,  7,  8,  9,
                                      10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21};
    for (bool big : {false, true}) {
        SCOPED_TRACE(big ? "big-endian" : "little-endian");
        NiftiFields f;
        f.big = big;
        f.voxOffset = 400; // room for an extension
        f.slope = 2.0f;
        f.inter = -1024.0f;
        const fs::path path = outDir() / (big ? "scaled_be.nii" : "scaled_le.nii");
        writeFile(path, niftiFile(f, bytesOf(raw, big)));
        const Volume v = loadVolume(path);
        EXPECT_EQ(v.dims, glm::ivec3(4, 3, 2));
        EXPECT_EQ(v.type, VoxelType::I16);
        EXPECT_EQ(v.spacing, glm::dvec3(1.5, 2, 2.5));
        ASSERT_EQ(v.values.size(), raw.size());
        for (size_t i = 0; i < raw.size(); ++i)
            EXPECT_EQ(v.values[i], 2.0f * raw[i] - 1024.0f);
        EXPECT_EQ(v.values.type(), VoxelType::I16) << "a whole slope and intercept within int16 keep 2 bytes a voxel";
        EXPECT_EQ(v.range.lo, -1028.0f);
        EXPECT_EQ(v.directions, glm::dmat3(1.0));
    }
}

TEST(NiftiLoad, GzipFloatWithSformAndUint16WithQform) {
    NiftiFields f;
    f.big = true;
    f.dim = {3, 2, 2, 2, 1, 1, 1, 1};
    f.datatype = 16;
    f.bitpix = 32;
    f.sformCode = 4;
    f.srow = {0, 0, -2, 10, 2, 0, 0, 20, 0, 3, 0, 30}; // axes permuted: x -> y, y -> z, z -> -x
    const std::vector<float> values = {0, 0.25f, -1, 2, 3, 4, 5, 6};
    writeFile(outDir() / "sform_f32.nii.gz", gzipBytes(niftiFile(f, bytesOf(values, true))));
    const Volume v = loadVolume(outDir() / "sform_f32.nii.gz");
    EXPECT_EQ(v.name, "sform_f32");
    EXPECT_EQ(v.type, VoxelType::F32);
    EXPECT_EQ(v.origin, glm::dvec3(10, 20, 30));
    EXPECT_EQ(v.directions, glm::dmat3(glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1), glm::dvec3(-1, 0, 0)));
    EXPECT_EQ(v.values, values);

    NiftiFields q;
    q.dim = {4, 2, 2, 1, 1, 1, 1, 1}; // 4D with one time point is a 3D volume
    q.datatype = 512;
    q.qformCode = 1;
    q.pixdim[0] = -1;               // qfac flips z
    q.quatern = {0, 0, 1, 5, 6, 7}; // 180 degrees about z
    writeFile(outDir() / "qform_u16.nii",
              niftiFile(q, bytesOf(std::vector<uint16_t>{1, 2, 3, 65535}, false)));
    const Volume u = loadVolume(outDir() / "qform_u16.nii");
    EXPECT_EQ(u.type, VoxelType::U16);
    EXPECT_EQ(u.origin, glm::dvec3(5, 6, 7));
    EXPECT_EQ(u.directions, glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1)));
    EXPECT_EQ(u.values, (std::vector<uint16_t>{1, 2, 3, 65535})) << "held as the file stores them";
}

// == SLC and DAT

TEST(SlcLoad, RunLengthAndRawSlicesDecode) {
    // 4x4 slices: run of 8 fives, 8 literal bytes, end; then a run of 16 nines.
    const std::string literal = rampBytes(8);
    const std::string rle0 = std::string("\x08\x05\x88", 3) + literal + std::string(1, '\0');
    const std::string rle1("\x10\x09\x00", 3);
    writeFile(outDir() / "rle.slc", slcFile({4, 4, 2}, 1, {rle0, rle1}));
    const Volume v = loadVolume(outDir() / "rle.slc");
    EXPECT_EQ(v.dims, glm::ivec3(4, 4, 2));
    EXPECT_EQ(v.spacing, glm::dvec3(1, 1, 2));
    for (size_t i = 0; i < 8; ++i)
        EXPECT_EQ(v.values[i], 5.0f);
    for (size_t i = 0; i < 8; ++i)
        EXPECT_EQ(v.values[8 + i], float(uint8_t(literal[i])));
    for (size_t i = 16; i < 32; ++i)
        EXPECT_EQ(v.values[i], 9.0f);

    writeFile(outDir() / "raw.slc", slcFile({4, 2, 2}, 0, {rampBytes(8), rampBytes(16).substr(8)}));
    const Volume r = loadVolume(outDir() / "raw.slc");
    const std::string ramp = rampBytes(16);
    for (size_t i = 0; i < 16; ++i)
        EXPECT_EQ(r.values[i], float(uint8_t(ramp[i])));
}

TEST(DatLoad, Uint16DimsHeaderThenVoxels) {
    const std::vector<uint16_t> values = {0, 1, 4095, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    writeFile(outDir() / "ct12bit.dat", datFile(3, 2, 2, bytesOf(values, false)));
    const Volume v = loadVolume(outDir() / "ct12bit.dat");
    EXPECT_EQ(v.name, "ct12bit");
    EXPECT_EQ(v.dims, glm::ivec3(3, 2, 2));
    EXPECT_EQ(v.type, VoxelType::U16);
    for (size_t i = 0; i < values.size(); ++i)
        EXPECT_EQ(v.values[i], float(values[i]));
}

TEST(NrrdLoad, Bzip2EncodingDecodes) {
    // Python: bz2.compress(struct.pack('<8f', 0, 1, 2, 3, -4, 5.5, 6, 7))
    const std::string bz(
        "\x42\x5a\x68\x39\x31\x41\x59\x26\x53\x59\x38\xd7\xa6\x22\x00\x00\x00\x4c\x4d\x50\x00\x00\x00"
        "\xc0\x00\x40\x00\x40\x00\x40\x00\x40\x00\x20\x00\x31\x0c\x08\x12\xa7\x88\x6a\x45\x10\xce\x43"
        "\x03\x6b\x97\x65\x47\x23\xe2\xee\x48\xa7\x0a\x12\x07\x1a\xf4\xc4\x40",
        63);
    writeFile(outDir() / "bz.nrrd",
              "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: bzip2\n\n" + bz);
    try {
        const Volume v = loadVolume(outDir() / "bz.nrrd");
        EXPECT_EQ(v.values, (std::vector<float>{0, 1, 2, 3, -4, 5.5f, 6, 7}));
    } catch (const LoadError& e) {
        // Only a build without libbz2 may refuse, and it must say why.
        EXPECT_TRUE(contains(e.what(), "libbz2")) << e.what();
    }
}

// == Image stacks (OpenImageIO writes the slices)

template <class T>
void writeSlice(const fs::path& path, int w, int h, OIIO::TypeDesc type, const std::vector<T>& pixels,
                int channels = 1) {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out) << OIIO::geterror();
    ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(w, h, channels, type))) << out->geterror();
    ASSERT_TRUE(out->write_image(type, pixels.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

TEST(ImageStackLoad, FolderOfPngSlicesInNumberOrder) {
    const fs::path dir = outDir() / "png_stack";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // Names sort wrongly as text (10 < 2): the loader orders by number.
    for (int z : {1, 2, 10}) {
        std::vector<uint8_t> pixels(5 * 4);
        for (size_t i = 0; i < pixels.size(); ++i)
            pixels[i] = uint8_t(z * 20 + int(i));
        writeSlice(dir / ("slice" + std::to_string(z) + ".png"), 5, 4, OIIO::TypeDesc::UINT8, pixels);
    }
    writeFile(dir / "notes.txt", "not a slice");
    const Volume v = loadVolume(dir);
    EXPECT_EQ(v.dims, glm::ivec3(5, 4, 3));
    EXPECT_EQ(v.type, VoxelType::U8);
    EXPECT_EQ(v.at(0, 0, 0), 20.0f);
    EXPECT_EQ(v.at(4, 3, 1), 40.0f + 19.0f);
    EXPECT_EQ(v.at(1, 0, 2), 201.0f);
}

// SLC files report a slice at a time, folders of slices a file at a time; a callback that says stop
// ends the read with Cancelled (the editor's Cancel).
TEST(ImageStackLoad, SlicesAndSlcReportProgressAndStopWhenCancelled) {
    const fs::path dir = outDir() / "progress_stack";
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (int z = 0; z < 4; ++z)
        writeSlice(dir / ("s" + std::to_string(z) + ".png"), 3, 2, OIIO::TypeDesc::UINT8, std::vector<uint8_t>(6, 7));
    writeFile(outDir() / "progress.slc",
              slcFile({4, 2, 4}, 0, {rampBytes(8), rampBytes(8), rampBytes(8), rampBytes(8)}));
    for (const fs::path& path : {dir, outDir() / "progress.slc"}) {
        std::vector<double> seen;
        loadVolume(path, std::nullopt, [&](double f) {
            seen.push_back(f);
            return true;
        });
        EXPECT_EQ(seen, (std::vector<double>{0.25, 0.5, 0.75, 1.0})) << path;
        int calls = 0;
        EXPECT_THROW(loadVolume(path, std::nullopt, [&](double f) { return ++calls, f < 0.5; }), Cancelled) << path;
        EXPECT_EQ(calls, 2) << path;
    }
}

TEST(ImageStackLoad, NumberedTiffPatternAndMultiPageTiff) {
    const fs::path dir = outDir() / "tif_pattern";
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (int z = 0; z < 3; ++z)
        writeSlice(dir / ("ct_" + std::string(z < 10 ? "00" : "0") + std::to_string(z) + ".tif"), 2, 2,
                   OIIO::TypeDesc::UINT16, std::vector<uint16_t>{uint16_t(z), 1000, 40000, 65535});
    const Volume v = loadVolume(dir / "ct_%03d.tif");
    EXPECT_EQ(v.dims, glm::ivec3(2, 2, 3));
    EXPECT_EQ(v.type, VoxelType::U16);
    EXPECT_EQ(v.at(0, 0, 2), 2.0f);
    EXPECT_EQ(v.range.hi, 65535.0f);

    // Multi-page: int16 Hounsfield pages, written as subimages of one TIFF.
    const fs::path multi = outDir() / "pages.tif";
    auto out = OIIO::ImageOutput::create(multi.string());
    ASSERT_TRUE(out && out->supports("multiimage"));
    const OIIO::ImageSpec spec(3, 1, 1, OIIO::TypeDesc::INT16);
    const std::vector<OIIO::ImageSpec> specs(2, spec);
    ASSERT_TRUE(out->open(multi.string(), 2, specs.data())) << out->geterror();
    const std::vector<int16_t> page0 = {-1024, 0, 3071}, page1 = {-1, 1, 2};
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::INT16, page0.data()));
    ASSERT_TRUE(out->open(multi.string(), spec, OIIO::ImageOutput::AppendSubimage));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::INT16, page1.data()));
    ASSERT_TRUE(out->close());
    const Volume p = loadVolume(multi);
    EXPECT_EQ(p.dims, glm::ivec3(3, 1, 2));
    EXPECT_EQ(p.type, VoxelType::I16);
    EXPECT_EQ(p.values, (std::vector<int16_t>{-1024, 0, 3071, -1, 1, 2}));
}

TEST(ImageStackLoad, MismatchedSlicesColourAndGapsAreRefused) {
    const fs::path dir = outDir() / "bad_stacks";
    fs::remove_all(dir);
    for (const char* sub : {"sizes", "rgb", "gap", "empty", "junk", "same_number"})
        fs::create_directories(dir / sub);
    writeSlice(dir / "sizes" / "a1.png", 4, 4, OIIO::TypeDesc::UINT8, std::vector<uint8_t>(16));
    writeSlice(dir / "sizes" / "a2.png", 4, 5, OIIO::TypeDesc::UINT8, std::vector<uint8_t>(20));
    expectLoadError(dir / "sizes", {"field 'slice size'", "a2.png", "4x5", "expected 4x4 uint8"});
    writeSlice(dir / "rgb" / "c.png", 2, 2, OIIO::TypeDesc::UINT8, std::vector<uint8_t>(12), 3);
    expectLoadError(dir / "rgb", {"field 'channels'", "3 channels, expected 1"});
    for (int z : {0, 1, 3})
        writeSlice(dir / "gap" / ("s" + std::to_string(z) + ".png"), 2, 2, OIIO::TypeDesc::UINT8,
                   std::vector<uint8_t>(4));
    expectLoadError(dir / "gap" / "s%d.png", {"slice 2 is missing"});
    expectLoadError(dir / "empty", {"no .tif, .tiff or .png slices"});
    writeFile(dir / "junk" / "broken.png", "\x89PNG\r\n\x1a\n but nothing after");
    expectLoadError(dir / "junk", {"broken.png"});
    expectLoadError(dir / "gap" / "none%d.png", {"no file", "matches the slice pattern"});
    for (const char* name : {"slice_1.png", "slice_01.png", "slice_2.png"})
        writeSlice(dir / "same_number" / name, 2, 2, OIIO::TypeDesc::UINT8, std::vector<uint8_t>(4));
    expectLoadError(dir / "same_number", {"field 'slices'", "slice_1.png", "slice_01.png", "the same number"});
}

// == The real originals in ../shared, against their raw copies

struct Original {
    const char* file; // in originals/
    const char* copy; // the converted header in the folder above
    glm::dvec3 origin;
    glm::dmat3 directions;
    uint32_t checksum; // voxelChecksum() of both
};

TEST(SharedOriginals, LoadAndMatchTheirRawCopiesVoxelForVoxel) {
    SPLATLAB_REQUIRE_SHARED_DATA(dir);
    const glm::dmat3 flipYZ(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1));
    // LIDC2's TransformMatrix flips y and z, but its voxels are stored in the same order as the copy
    // (which was decoded from the VTK file without a direction): the stored order is compared, and the
    // flip is checked as metadata in Volume::directions.
    const Original originals[] = {
        {"HeadMRVolume.mhd", "head_mr.nhdr", {0, 0, 0}, glm::dmat3(1.0), 0},
        {"LIDC2.mha", "lidc2_chest_ct.nhdr", {0, 360, 332.5}, flipYZ, 0},
        {"avg152T1_RL_nifti.nii.gz", "mni_avg152t1.nhdr", {-90, -126, -72}, glm::dmat3(1.0), 0},
        {"neghip.slc", "neghip.nhdr", {0, 0, 0}, glm::dmat3(1.0), 0},
    };
    for (const Original& o : originals) {
        SCOPED_TRACE(o.file);
        const Volume original = loadVolume(dir / "originals" / o.file);
        const Volume copy = loadVolume(dir / o.copy);
        EXPECT_EQ(original.dims, copy.dims);
        EXPECT_EQ(original.type, copy.type);
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_NEAR(original.spacing[axis], copy.spacing[axis], 1e-9);
            EXPECT_NEAR(original.origin[axis], o.origin[axis], 1e-9);
            for (int row = 0; row < 3; ++row)
                EXPECT_NEAR(original.directions[axis][row], o.directions[axis][row], 1e-12);
        }
        EXPECT_EQ(original.range.lo, copy.range.lo);
        EXPECT_EQ(original.range.hi, copy.range.hi);
        EXPECT_EQ(voxelChecksum(original), voxelChecksum(copy));
        EXPECT_TRUE(original.values == copy.values);
    }
}

TEST(SharedOriginals, EveryFileInTheFoldersLoads) {
    SPLATLAB_REQUIRE_SHARED_DATA(dir);
    int loaded = 0;
    for (const fs::path& folder : {dir, dir / "originals"}) {
        for (const auto& entry : fs::directory_iterator(folder)) {
            const std::string name = entry.path().filename().string();
            if (!entry.is_regular_file() || name == "MANIFEST.md") continue;
            // HeadMRVolume.raw is the .mhd's data file: loaded through its header.
            if (name == "HeadMRVolume.raw") continue;
            SCOPED_TRACE(name);
            const Volume v = loadVolume(entry.path());
            EXPECT_EQ(v.values.size(), v.voxelCount());
            EXPECT_GT(v.voxelCount(), 0u);
            ++loaded;
        }
    }
    EXPECT_EQ(loaded, 4 + 11 + 10); // originals, headers, raw data files named by their layout
}

// == Malformed files of the new formats: LoadError naming the file, the field and what was expected

struct BadFile {
    std::string file;
    std::string content;
    std::vector<std::string> expect;
};
void PrintTo(const BadFile& b, std::ostream* os) { *os << b.file; }

std::string mha(const std::string& fields, const std::string& data = rampBytes(24)) {
    return "ObjectType = Image\nNDims = 3\n" + fields + "ElementDataFile = LOCAL\n" + data;
}
const std::string kMhaOk = "DimSize = 4 3 2\nElementType = MET_UCHAR\n";

NiftiFields niftiWith(void (*edit)(NiftiFields&)) {
    NiftiFields f;
    edit(f);
    return f;
}
std::string nii(void (*edit)(NiftiFields&), size_t dataBytes = 48) {
    return niftiFile(niftiWith(edit), rampBytes(dataBytes));
}

std::vector<BadFile> badFiles() {
    const std::string rle16("\x10\x09\x00", 3);
    return {
        // MetaImage
        {"mha_missing_dimsize.mha", mha("ElementType = MET_UCHAR\n"), {"field 'DimSize': missing"}},
        {"mha_ndims_2.mha",
         "NDims = 2\nDimSize = 4 4\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
         {"field 'NDims': '2', expected 3"}},
        {"mha_negative_dim.mha",
         mha("DimSize = 4 -3 2\nElementType = MET_UCHAR\n"),
         {"field 'DimSize'", "-3", "positive"}},
        {"mha_overflowing_dims.mha",
         mha("DimSize = 100000 100000 100000\nElementType = MET_UCHAR\n"),
         {"field 'DimSize'", "100000 x 100000 x 100000", "more than"}},
        {"mha_double.mha",
         mha("DimSize = 4 3 2\nElementType = MET_DOUBLE\n"),
         {"field 'ElementType': 'MET_DOUBLE' is not supported", "MET_UCHAR"}},
        {"mha_zero_spacing.mha",
         mha(kMhaOk + "ElementSpacing = 1 0 1\n"),
         {"field 'ElementSpacing'", "spacing 0 on axis 1", "finite positive"}},
        {"mha_nan_spacing.mha",
         mha(kMhaOk + "ElementSpacing = nan 1 1\n"),
         {"field 'ElementSpacing'", "'nan' is not a finite number"}},
        {"mha_negative_spacing.mha",
         mha(kMhaOk + "ElementSpacing = 1 1 -2\n"),
         {"field 'ElementSpacing'", "spacing -2 on axis 2"}},
        {"mha_truncated.mha",
         mha(kMhaOk, rampBytes(20)),
         {"field 'data'", "has 20 bytes after the header, expected 24 bytes"}},
        {"mha_zlib_garbage.mha",
         mha(kMhaOk + "CompressedData = True\n", "\x78\x9c garbage garbage"),
         {"field 'data'", "stream is corrupt"}},
        {"mha_zlib_lying.mha",
         mha("DimSize = 1000 1000 300\nElementType = MET_UCHAR\nCompressedData = True\n",
             zlibBytes(rampBytes(24))),
         {"field 'data'", "cannot hold 300000000 bytes", "1032:1"}},
        {"mha_no_data_file.mha",
         "NDims = 3\nDimSize = 4 3 2\nElementType = MET_UCHAR\n",
         {"field 'ElementDataFile': missing"}},
        {"mha_three_channels.mha",
         mha(kMhaOk + "ElementNumberOfChannels = 3\n"),
         {"field 'ElementNumberOfChannels': '3', expected 1"}},
        {"mha_ascii.mha", mha(kMhaOk + "BinaryData = False\n"), {"field 'BinaryData'", "ASCII"}},
        {"mha_singular_matrix.mha",
         mha(kMhaOk + "TransformMatrix = 1 0 0 1 0 0 0 0 1\n"),
         {"field 'TransformMatrix'", "singular"}},
        {"mha_bad_bool.mha",
         mha(kMhaOk + "ElementByteOrderMSB = Maybe\n"),
         {"field 'ElementByteOrderMSB': 'Maybe', expected True or False"}},
        {"mha_binary_junk.mha", std::string(300, '\x01'), {"line 1 is not 'Key = Value'"}},
        {"mhd_missing_data.mhd",
         "NDims = 3\nDimSize = 4 3 2\nElementType = MET_UCHAR\nElementDataFile = nowhere.raw\n",
         {"field 'data file'", "nowhere.raw", "cannot open"}},
        {"mhd_list.mhd",
         "NDims = 3\nDimSize = 4 3 2\nElementType = MET_UCHAR\nElementDataFile = LIST\n",
         {"field 'ElementDataFile'", "not supported"}},
        {"mha_duplicate.mha",
         mha(kMhaOk + "DimSize = 1 1 1\n"),
         {"field 'DimSize': appears twice (lines 3 and 5)"}},
        // NIfTI-1
        {"nii_short.nii",
         std::string(100, '\0'),
         {"field 'sizeof_hdr'", "has 100 bytes, expected a 348-byte NIfTI-1 header"}},
        {"nii_bad_sizeof_hdr.nii",
         nii([](NiftiFields& f) { f.sizeofHdr = 1234; }),
         {"field 'sizeof_hdr': 1234", "expected 348"}},
        {"nii_version_2.nii",
         nii([](NiftiFields& f) { f.sizeofHdr = 540; }) + std::string(200, '\0'),
         {"field 'sizeof_hdr': 540 (NIfTI-2, not supported)"}},
        {"nii_bad_magic.nii",
         nii([](NiftiFields& f) { f.magic = "abcd"; }),
         {"field 'magic': 'abcd', expected 'n+1'"}},
        {"nii_pair.nii",
         nii([](NiftiFields& f) { f.magic = std::string("ni1\0", 4); }),
         {"field 'magic'", ".hdr/.img pair"}},
        {"nii_time_series.nii",
         nii([](NiftiFields& f) { f.dim = {4, 4, 3, 2, 5, 1, 1, 1}; }),
         {"field 'dim[4]': 5, expected 1"}},
        {"nii_rank_2.nii", nii([](NiftiFields& f) { f.dim[0] = 2; }), {"field 'dim[0]': 2, expected 3"}},
        {"nii_negative_dim.nii",
         nii([](NiftiFields& f) { f.dim[2] = -3; }),
         {"field 'dim'", "-3", "positive"}},
        {"nii_float64.nii",
         nii([](NiftiFields& f) {
             f.datatype = 64;
             f.bitpix = 64;
         }),
         {"field 'datatype': 64 (float64) is not supported", "2 uint8"}},
        {"nii_unknown_type.nii",
         nii([](NiftiFields& f) { f.datatype = 99; }),
         {"field 'datatype': 99 is not supported"}},
        {"nii_bitpix.nii",
         nii([](NiftiFields& f) { f.bitpix = 8; }),
         {"field 'bitpix': 8, expected 16 for int16"}},
        {"nii_zero_pixdim.nii",
         nii([](NiftiFields& f) { f.pixdim[2] = 0; }),
         {"field 'pixdim'", "spacing 0 on axis 1"}},
        {"nii_negative_pixdim.nii",
         nii([](NiftiFields& f) { f.pixdim[3] = -2.5f; }),
         {"field 'pixdim'", "spacing -2.5 on axis 2"}},
        {"nii_nan_pixdim.nii",
         nii([](NiftiFields& f) { f.pixdim[1] = NAN; }),
         {"field 'pixdim'", "spacing nan on axis 0"}},
        {"nii_small_vox_offset.nii",
         nii([](NiftiFields& f) { f.voxOffset = 0; }),
         {"field 'vox_offset': 0, expected a whole number of bytes >= 348"}},
        {"nii_nan_vox_offset.nii",
         nii([](NiftiFields& f) { f.voxOffset = NAN; }),
         {"field 'vox_offset': nan"}},
        {"nii_truncated.nii",
         nii([](NiftiFields&) {}, 40),
         {"field 'data'", "has 392 bytes", "expected 400 bytes (a 352-byte skip, then 48 bytes of 4x3x2 int16)"}},
        {"nii_inf_slope.nii",
         nii([](NiftiFields& f) { f.slope = INFINITY; }),
         {"field 'scl_slope': inf, expected a finite number"}},
        // Finite, but the stored values times it are not floats any more: they would turn into +inf.
        {"nii_overflowing_slope.nii",
         nii([](NiftiFields& f) { f.slope = 3e38f; }),
         {"field 'scl_slope'", "within a 32-bit float's range"}},
        {"nii_tiny_pixdim.nii",
         nii([](NiftiFields& f) { f.pixdim[1] = 1e-30f; }),
         {"field 'pixdim'", "expected 1e-06 to 1e+06"}},
        {"nii_huge_pixdim.nii",
         nii([](NiftiFields& f) { f.pixdim[3] = 1e30f; }),
         {"field 'pixdim'", "spacing 1e+30 on axis 2", "expected 1e-06 to 1e+06"}},
        // b^2 + c^2 + d^2 = 1.5: no unit quaternion has these parts.
        {"nii_non_unit_quaternion.nii",
         nii([](NiftiFields& f) {
             f.qformCode = 1;
             f.quatern = {0.5f, 1.0f, 0.5f, 0, 0, 0};
         }),
         {"field 'quatern_b/c/d'", "expected at most 1"}},
        {"nii_gz_garbage.nii.gz",
         std::string("\x1f\x8b\x08\x00garbage-garbage-garbage", 27),
         {"field 'data'", "stream is corrupt"}},
        {"nii_gz_truncated.nii.gz",
         gzipBytes(nii([](NiftiFields&) {})).substr(0, 20),
         {"field 'sizeof_hdr'", "gzip stream has", "expected a 348-byte"}},
        // VolVis SLC
        {"slc_bad_magic.slc", "12345\n4 4 1 8\n", {"field 'magic': 12345, expected 11111"}},
        {"slc_16_bits.slc",
         slcFile({4, 4, 1}, 1, {rle16}, "1 1 1", 16),
         {"field 'bits_per_voxel': 16, expected 8"}},
        {"slc_zero_unit.slc",
         slcFile({4, 4, 1}, 1, {rle16}, "1 0 1"),
         {"field 'x/y/z_unit'", "spacing 0 on axis 1"}},
        {"slc_run_overflows.slc",
         slcFile({4, 4, 1}, 1, {std::string("\x7f\x09\x00", 3)}),
         {"field 'slice 0'", "more than the 16 voxels"}},
        {"slc_run_short.slc",
         slcFile({4, 4, 1}, 1, {std::string("\x0f\x09\x00", 3)}),
         {"field 'slice 0'", "decodes to 15 voxels, expected 16"}},
        {"slc_literal_past_end.slc",
         slcFile({4, 4, 1}, 1, {std::string("\x90\x01\x02", 3)}),
         {"field 'slice 0'", "literal run of 16 bytes passes the end"}},
        {"slc_truncated.slc",
         slcFile({4, 4, 2}, 1, {rle16}),
         {"field 'slice 1 size'", "expected an integer"}},
        {"slc_slice_size_lies.slc",
         slcFile({4, 4, 1}, 1, {}) + "9999 X\x10\x09",
         {"field 'slice 0'", "needs 9999 bytes"}},
        {"slc_lying_dims.slc",
         slcFile({5000, 5000, 12}, 1, {rle16}),
         {"field 'data'", "cannot hold 5000x5000x12 uint8 run-length encoded"}},
        {"slc_no_marker.slc", "11111\n4 4 1 8\n1 1 1\n1 6 0 1\n2 2 Y", {"field 'icon size'", "expected 'X'"}},
        {"slc_compression_2.slc",
         slcFile({4, 4, 1}, 2, {rle16}),
         {"field 'data_compression': 2, expected 0 (none) or 1"}},
        {"slc_raw_wrong_size.slc",
         slcFile({4, 4, 1}, 0, {rampBytes(15)}),
         {"field 'slice 0 size': 15, expected 16"}},
        // DAT
        {"dat_short_header.dat",
         std::string("\x04\x00\x04", 3),
         {"field 'dims'", "3 bytes, expected a 6-byte header"}},
        {"dat_zero_dim.dat", datFile(4, 0, 4, ""), {"field 'dims'", "size 0 must be a positive integer"}},
        {"dat_truncated.dat",
         datFile(4, 4, 4, rampBytes(100)),
         {"field 'data'", "has 100 bytes after the header, expected 128 bytes (4x4x4 uint16)"}},
        {"dat_trailing.dat", datFile(2, 2, 2, rampBytes(17)), {"field 'data'", "1 trailing bytes"}},
        // NRRD compression
        {"nrrd_gzip_lying.nrrd",
         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1200 1200 200\nencoding: gzip\n\n" + gzipBytes("tiny"),
         {"field 'data'", "cannot hold 288000000 bytes"}},
        {"nrrd_bzip2_garbage.nrrd",
         "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: bzip2\n\nBZh9garbage",
         {"bzip2"}},
    };
}

class MalformedFormatFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(MalformedFormatFile, ThrowsLoadErrorNamingFileFieldAndExpectation) {
    const BadFile& c = GetParam();
    const fs::path path = outDir() / c.file;
    writeFile(path, c.content);
    expectLoadError(path, c.expect);
}

INSTANTIATE_TEST_SUITE_P(VolumeFormats, MalformedFormatFile, ::testing::ValuesIn(badFiles()),
                         [](const auto& info) {
                             return info.param.file.substr(0, info.param.file.find('.'));
                         });

TEST(VolumeIoErrors, DevicesAndFifosAreNotRead) {
    expectLoadError("/dev/null", {"unknown file type"});
    const fs::path fifoHeader = outDir() / "fifo_data.nhdr";
    writeFile(fifoHeader,
              "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\ndata file: /dev/zero\n");
    expectLoadError(fifoHeader, {"field 'data file'", "/dev/zero", "not a regular file"});
}

} // namespace
