// Volume loading (raw, NRRD attached/detached, gzip), range, histogram and the procedural volumes.
// Malformed files are written by the tests into the test output folder; the shared datasets are optional.
#include "renderer/errors.h"
#include "renderer/model/procedural.h"
#include "renderer/io/volume_io.h"
#include "scoped_env.h"
#include "test_paths.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <vector>

using namespace renderer;
namespace fs = std::filesystem;

namespace {

fs::path outDir() { return testing_support::testOutputDir("volume_io"); }

void writeFile(const fs::path& path, const std::string& bytes) {
    ASSERT_TRUE(testing_support::writeFile(path, bytes)) << "cannot write " << path;
}

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Compresses through zlib's gzip file API, the way other tools write .gz files. The scratch file is
// named after the running test because ctest -j runs each test in its own process at the same time.
std::string gzipBytes(const std::string& bytes) {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string scratch = std::string(test->test_suite_name()) + "." + test->name() + ".scratch.gz";
    std::replace(scratch.begin(), scratch.end(), '/', '_');
    const fs::path tmp = outDir() / scratch;
    gzFile gz = gzopen(tmp.string().c_str(), "wb");
    EXPECT_NE(gz, nullptr);
    EXPECT_EQ(gzwrite(gz, bytes.data(), unsigned(bytes.size())), int(bytes.size()));
    EXPECT_EQ(gzclose(gz), Z_OK);
    return readFile(tmp);
}

// A byte pattern with period 251 (prime): a read shifted by any voxel size or header length is caught.
std::string rampBytes(size_t n) {
    std::string s(n, '\0');
    for (size_t i = 0; i < n; ++i) s[i] = char(i * 7 % 251);
    return s;
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
    if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

// == Shared datasets (../shared/data/volumes), checked against the numbers in its MANIFEST.md

struct Dataset {
    const char* file;
    glm::ivec3 dims;
    VoxelType type;
    glm::dvec3 spacing;
    float lo, hi;
};

const std::vector<Dataset> kDatasets = {
    {"bonsai.nhdr", {256, 256, 256}, VoxelType::U8, {1, 1, 1}, 0, 255},
    {"engine.nhdr", {256, 256, 128}, VoxelType::U8, {1, 1, 1}, 0, 255},
    {"aneurism.nhdr", {256, 256, 256}, VoxelType::U8, {1, 1, 1}, 0, 255},
    {"tooth.nrrd", {103, 94, 161}, VoxelType::U8, {1, 1, 1}, 0, 255},
    {"lidc2_chest_ct.nhdr", {256, 256, 133}, VoxelType::U8, {1.40625, 1.40625, 2.5}, 0, 255},
    {"neghip.nhdr", {66, 66, 66}, VoxelType::U8, {1, 1, 1}, 0, 255},
    {"hydrogen.nhdr", {64, 64, 64}, VoxelType::F32, {1, 1, 1}, 0, 1},
    {"headsq.nhdr", {64, 64, 93}, VoxelType::I16, {3.2, 3.2, 1.5}, 0, 3926},
    {"head_mr.nhdr", {48, 62, 42}, VoxelType::U8, {4, 4, 4}, 0, 255},
    {"embryo.nhdr", {256, 256, 256}, VoxelType::U8, {1, 1, 1}, 0, 197},
    {"mni_avg152t1.nhdr", {91, 109, 91}, VoxelType::U8, {2, 2, 2}, 0, 255},
};

TEST(SharedVolumes, EveryHeaderInTheFolderIsInTheManifestTable) {
    SPLATLAB_REQUIRE_SHARED_DATA(dir);
    std::set<std::string> known;
    for (const Dataset& d : kDatasets) known.insert(d.file);
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string ext = entry.path().extension().string();
        if (ext == ".nhdr" || ext == ".nrrd") {
            EXPECT_TRUE(known.count(entry.path().filename().string())) << entry.path();
        }
    }
}

TEST(SharedVolumes, LoadWithTheManifestDimsTypeSpacingAndRange) {
    SPLATLAB_REQUIRE_SHARED_DATA(dir);
    for (const Dataset& d : kDatasets) {
        SCOPED_TRACE(d.file);
        const Volume v = loadVolume(dir / d.file);
        EXPECT_EQ(v.dims, d.dims);
        EXPECT_EQ(v.type, d.type);
        for (int axis = 0; axis < 3; ++axis) EXPECT_DOUBLE_EQ(v.spacing[axis], d.spacing[axis]);
        EXPECT_EQ(v.origin, glm::dvec3(0.0));
        EXPECT_EQ(v.values.size(), v.voxelCount());
        EXPECT_EQ(v.range.lo, d.lo);   // exact: hydrogen's float32 data also spans exactly 0..1
        EXPECT_EQ(v.range.hi, d.hi);
        EXPECT_EQ(v.name, fs::path(d.file).stem().string());
    }
}

TEST(SharedVolumes, HeadsqRangeIsZeroTo3926) {
    SPLATLAB_REQUIRE_SHARED_DATA(dir);
    const Volume v = loadNrrd(dir / "headsq.nhdr");
    EXPECT_EQ(v.range.lo, 0.0f);
    EXPECT_EQ(v.range.hi, 3926.0f);
}

TEST(SharedVolumes, RawByFileNameMatchesNrrdVoxelForVoxel) {
    SPLATLAB_REQUIRE_SHARED_DATA(dir);
    struct Pair {
        const char* header;
        const char* raw;
        const char* rawName;   // the raw file's volume name: its file name without .raw[.gz]
    };
    const Pair pairs[] = {
        {"head_mr.nhdr", "head_mr_48x62x42_uint8.raw", "head_mr_48x62x42_uint8"},
        {"headsq.nhdr", "headsq_64x64x93_int16.raw", "headsq_64x64x93_int16"},
        {"hydrogen.nhdr", "hydrogen_64x64x64_float32.raw", "hydrogen_64x64x64_float32"},
        {"lidc2_chest_ct.nhdr", "lidc2_chest_ct_256x256x133_uint8.raw.gz",
         "lidc2_chest_ct_256x256x133_uint8"},
    };
    for (const auto& [header, raw, rawName] : pairs) {
        SCOPED_TRACE(raw);
        const Volume fromNrrd = loadVolume(dir / header);
        const Volume fromRaw = loadVolume(dir / raw);
        EXPECT_EQ(fromRaw.dims, fromNrrd.dims);
        EXPECT_EQ(fromRaw.type, fromNrrd.type);
        EXPECT_TRUE(fromRaw.values == fromNrrd.values);
        EXPECT_EQ(fromRaw.name, rawName);
    }
}

TEST(BundledVolumes, AssetsLoad) {
    const fs::path dir = testing_support::assetDir() / "volumes";
    const Volume headsq = loadVolume(dir / "headsq.nhdr");
    EXPECT_EQ(headsq.dims, glm::ivec3(64, 64, 93));
    EXPECT_EQ(headsq.range.hi, 3926.0f);
    const Volume neghip = loadVolume(dir / "neghip.nhdr");
    EXPECT_EQ(neghip.dims, glm::ivec3(66));
    EXPECT_EQ(neghip.range.hi, 255.0f);
    const Volume bonsai = loadVolume(dir / "bonsai.nhdr");   // the editor's default volume
    EXPECT_EQ(bonsai.dims, glm::ivec3(128));
    EXPECT_EQ(bonsai.spacing, glm::dvec3(2.0));
    EXPECT_EQ(bonsai.range.hi, 255.0f);
}

// assets/volumes/MANIFEST.md: the bundled bonsai is the shared 256^3 scan, each 2x2x2 block's mean
// rounded half up, and nothing else.
TEST(BundledVolumes, BonsaiIsTheSharedScansRoundedTwoByTwoByTwoBlockMeans) {
    SPLATLAB_REQUIRE_SHARED_DATA(dir);
    const Volume fine = loadVolume(dir / "bonsai.nhdr");
    const Volume coarse = loadVolume(testing_support::assetDir() / "volumes" / "bonsai.nhdr");
    ASSERT_EQ(fine.dims, glm::ivec3(256));
    ASSERT_EQ(coarse.dims, glm::ivec3(128));
    EXPECT_EQ(coarse.spacing, 2.0 * fine.spacing);
    size_t mismatches = 0;
    for (int z = 0; z < 128; ++z)
        for (int y = 0; y < 128; ++y)
            for (int x = 0; x < 128; ++x) {
                int sum = 0;
                for (int c = 0; c < 8; ++c) sum += int(fine.at(2 * x + (c & 1), 2 * y + (c >> 1 & 1), 2 * z + (c >> 2)));
                mismatches += int(coarse.at(x, y, z)) != (sum + 4) / 8;
            }
    EXPECT_EQ(mismatches, 0u);
}

// == Files written by the tests

TEST(RawFileName, ParsesDimsAndType) {
    auto o = rawOptionsFromFileName("dir/headsq_64x64x93_int16.raw");
    ASSERT_TRUE(o);
    EXPECT_EQ(o->dims, glm::ivec3(64, 64, 93));
    EXPECT_EQ(o->type, VoxelType::I16);
    EXPECT_EQ(o->endian, Endian::Little);
    o = rawOptionsFromFileName("a_b_1x2x3_float.raw.gz");
    ASSERT_TRUE(o);
    EXPECT_EQ(o->dims, glm::ivec3(1, 2, 3));
    EXPECT_EQ(o->type, VoxelType::F32);
    EXPECT_EQ(rawOptionsFromFileName("_4x5x6_uint16.raw")->type, VoxelType::U16);
    for (const char* bad : {"plain.raw", "x_1x2_uint8.raw", "x_1x2x3_int32.raw", "x_1x0x3_uint8.raw",
                            "x_1x2x3_uint8.nrrd", "x_1x2x3x4_uint8.raw", "x_99999999999x2x3_uint8.raw"})
        EXPECT_FALSE(rawOptionsFromFileName(bad)) << bad;
}

TEST(RawLoad, BigEndianRoundTrip) {
    // 3x2x2 voxels of each multi-byte type, written big-endian after a 5-byte header.
    const std::vector<float> values = {0, 1, -2, 300, -32768, 32767, 7, 8, 9, 10, 11, 12};
    RawOptions options;
    options.dims = {3, 2, 2};
    options.endian = Endian::Big;
    options.headerBytes = 5;
    options.spacing = {0.5, 1.0, 2.0};
    for (VoxelType type : {VoxelType::I16, VoxelType::U16, VoxelType::F32}) {
        SCOPED_TRACE(voxelTypeName(type));
        std::string bytes = "HEAD!";
        for (float v : values) {
            const float stored = type == VoxelType::U16 ? std::abs(v) : v;
            const uint32_t bits = type == VoxelType::F32 ? std::bit_cast<uint32_t>(stored)
                                                         : uint32_t(uint16_t(int32_t(stored)));
            for (int shift = int(voxelTypeBytes(type)) * 8 - 8; shift >= 0; shift -= 8)
                bytes += char(bits >> shift);
        }
        const fs::path path = outDir() / (std::string("big_endian_") + voxelTypeName(type) + ".raw");
        writeFile(path, bytes);
        options.type = type;
        const Volume v = loadRaw(path, options);
        EXPECT_EQ(v.type, type);
        EXPECT_EQ(v.spacing, options.spacing);
        ASSERT_EQ(v.values.size(), values.size());
        for (size_t i = 0; i < values.size(); ++i)
            EXPECT_EQ(v.values[i], type == VoxelType::U16 ? std::abs(values[i]) : values[i]) << "voxel " << i;
    }
}

// Streamed formats report the share of the voxels read, every 64 KiB, up to 1; a callback that
// returns false stops the read with Cancelled (the editor's Cancel), raw and gzip alike.
TEST(RawLoad, ReportsProgressAndStopsWhenCancelled) {
    const std::string data = rampBytes(size_t(64) * 64 * 64 * 2);   // 512 KiB of uint16: 8 chunks
    writeFile(outDir() / "progress_64x64x64_uint16.raw", data);
    writeFile(outDir() / "progress_64x64x64_uint16.raw.gz", gzipBytes(data));
    for (const char* name : {"progress_64x64x64_uint16.raw", "progress_64x64x64_uint16.raw.gz"}) {
        std::vector<double> seen;
        const Volume v = loadVolume(outDir() / name, std::nullopt, [&](double f) {
            seen.push_back(f);
            return true;
        });
        EXPECT_EQ(v.voxelCount(), size_t(64) * 64 * 64) << name;
        ASSERT_EQ(seen.size(), 8u) << name;
        EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end())) << name;
        EXPECT_DOUBLE_EQ(seen.front(), 0.125) << name;
        EXPECT_DOUBLE_EQ(seen.back(), 1.0) << name;
        int calls = 0;
        EXPECT_THROW(loadVolume(outDir() / name, std::nullopt, [&](double f) { return ++calls, f < 0.5; }), Cancelled)
            << name;
        EXPECT_EQ(calls, 4) << name << ": the read stops at the first false";
    }
}

TEST(RawLoad, GzipRawIsDetectedByMagicAndName) {
    const std::string data = rampBytes(4 * 3 * 2);
    writeFile(outDir() / "ramp_4x3x2_uint8.raw.gz", gzipBytes(data));
    writeFile(outDir() / "ramp_by_magic.raw", gzipBytes(data));   // no .gz: found by the 1f 8b magic
    const Volume byName = loadVolume(outDir() / "ramp_4x3x2_uint8.raw.gz");
    const Volume byMagic = loadVolume(outDir() / "ramp_by_magic.raw", RawOptions{.dims = {4, 3, 2}});
    EXPECT_EQ(byName.name, "ramp_4x3x2_uint8");
    for (const Volume* v : {&byName, &byMagic}) {
        ASSERT_EQ(v->values.size(), data.size());
        for (size_t i = 0; i < data.size(); ++i) EXPECT_EQ(v->values[i], float(uint8_t(data[i])));
    }
}

TEST(NrrdLoad, GzipDetachedAttachedAndSkippedLoad) {
    const std::string data = rampBytes(5 * 4 * 3 * 2);   // uint16 little-endian
    const std::string fields = "NRRD0005\ntype: unsigned short\ndimension: 3\nsizes: 5 4 3\nendian: little\n"
                               "encoding: gzip\n";
    writeFile(outDir() / "gz_detached.raw.gz", gzipBytes(data));
    writeFile(outDir() / "gz_detached.nhdr", fields + "data file: gz_detached.raw.gz\n");
    writeFile(outDir() / "gz_attached.nrrd", fields + "\n" + gzipBytes(data));
    // byte skip counts decompressed bytes for gzip data
    writeFile(outDir() / "gz_byte_skip.nrrd", fields + "byte skip: 3\n\n" + gzipBytes("XYZ" + data));
    for (const char* name : {"gz_detached.nhdr", "gz_attached.nrrd", "gz_byte_skip.nrrd"}) {
        SCOPED_TRACE(name);
        const Volume v = loadVolume(outDir() / name);
        EXPECT_EQ(v.type, VoxelType::U16);
        EXPECT_EQ(v.dims, glm::ivec3(5, 4, 3));
        ASSERT_EQ(v.values.size(), 60u);
        for (size_t i = 0; i < 60; ++i)
            EXPECT_EQ(v.values[i], float(uint8_t(data[2 * i]) | uint8_t(data[2 * i + 1]) << 8));
    }
}

TEST(NrrdLoad, HonoursSkipsDirectionsOriginAndSpellings) {
    // CRLF line endings, "datafile:" spelling, key:=value pairs, unknown fields, byte and line skips.
    const std::string data = rampBytes(2 * 2 * 2);
    writeFile(outDir() / "skips.raw", "two text\nlines\n" + std::string("XYZ") + data);
    writeFile(
        outDir() / "skips.nhdr",
        "NRRD0004\r\n# comment\r\nType: uchar\r\ndimension: 3\r\nsizes: 2 2 2\r\n"
        "space directions: (0,0.5,0) (3,4,0) (0,0,-2)\r\nspace origin: (1.5,-2,3)\r\nkinds: domain domain "
        "domain\r\nmodality:=CT\r\nencoding: raw\r\nline skip: 2\r\nbyte skip: 3\r\ndatafile: skips.raw\r\n");
    const Volume v = loadVolume(outDir() / "skips.nhdr");
    EXPECT_EQ(v.spacing, glm::dvec3(0.5, 5.0, 2.0));
    EXPECT_EQ(v.origin, glm::dvec3(1.5, -2.0, 3.0));
    EXPECT_EQ(v.name, "skips");
    for (size_t i = 0; i < data.size(); ++i) EXPECT_EQ(v.values[i], float(uint8_t(data[i])));
}

// == Malformed files: each must throw LoadError naming the file and the field (or the reason)

void expectLoadError(const fs::path& path, const std::vector<std::string>& expect) {
    try {
        loadVolume(path);
        ADD_FAILURE() << "expected LoadError for " << path;
    } catch (const LoadError& e) {
        const std::string msg = e.what();
        EXPECT_TRUE(contains(msg, path.string() + ": "));
        for (const std::string& part : expect) EXPECT_TRUE(contains(msg, part));
    }
}

// What a header's data file "<name>.data" holds; the unedited header wants 64 bytes of raw uint8.
enum class DataKind { Valid, ShortRaw, ShortGzip, TruncatedGzip, CorruptGzip };

struct BadHeader {
    std::string name;                  // test name; the header is "<name>.nhdr"
    std::vector<std::string> edits;    // changes to a valid header (see editedHeader)
    std::vector<std::string> expect;   // substrings of what() besides the file name
    DataKind data = DataKind::Valid;
};
// Short names in test listings (gtest would otherwise print the struct's bytes).
void PrintTo(const BadHeader& b, std::ostream* os) { *os << b.name; }

// A valid detached header for 4x4x4 uint8 raw data in "<name>.data", then `edits` in order:
// "field: value" replaces that field (or appends it), "+field: value" appends a line, "-field" drops it.
std::string editedHeader(const std::string& name, const std::vector<std::string>& edits) {
    std::vector<std::string> lines = {"type: uint8", "dimension: 3", "sizes: 4 4 4", "encoding: raw",
                                      "data file: " + name + ".data"};
    for (const std::string& edit : edits) {
        if (edit[0] == '+') {
            lines.push_back(edit.substr(1));
            continue;
        }
        const bool remove = edit[0] == '-';
        const std::string field = remove ? edit.substr(1) : edit.substr(0, edit.find(':'));
        const auto it = std::find_if(lines.begin(), lines.end(),
                                     [&](const std::string& line) { return line.starts_with(field + ":"); });
        if (it == lines.end())
            lines.push_back(edit);
        else if (remove)
            lines.erase(it);
        else
            *it = edit;
    }
    std::string text = "NRRD0004\n";
    for (const std::string& line : lines) text += line + "\n";
    return text;
}

const BadHeader kBadHeaders[] = {
    {"missing_sizes", {"-sizes"}, {"field 'sizes': missing"}},
    {"sizes_two_values", {"sizes: 4 4"}, {"field 'sizes': has 2 values, expected 3 (dimension: 3)"}},
    {"negative_size", {"sizes: 4 -4 4"}, {"'sizes'", "-4", "positive"}},
    {"overflowing_dims", {"sizes: 4000000000 4000000000 10"}, {"'sizes'", "4000000000 x 4000000000 x 10"}},
    // Refused from the header with the renderer's own limit, not after reading gigabytes.
    {"over_the_voxel_limit", {"sizes: 1024 1024 1024"},
     {"'sizes'", "1024 x 1024 x 1024 = 1073741824 voxels is more than the 715827882 SplatLab renders"}},
    {"axis_over_65535", {"sizes: 70000 2 2"}, {"'sizes'", "70000 voxels along an axis", "65535"}},
    {"zero_spacing", {"spacings: 1 0 1"}, {"'spacings'", "'0'", "positive"}},
    {"negative_spacing", {"spacings: 1 1 -2"}, {"'spacings'", "'-2'", "positive"}},
    {"nan_spacing", {"spacings: nan 1 1"}, {"'spacings'", "'nan'", "finite"}},
    // Finite and positive, but footprints square them: the volume rendered blank.
    {"denormal_spacing", {"spacings: 1e-320 1 1"}, {"'spacings'", "expected 1e-06 to 1e+06"}},
    {"huge_spacing", {"spacings: 1 1e300 1"}, {"'spacings'", "spacing 1e+300 on axis 1", "expected 1e-06 to 1e+06"}},
    {"unknown_type", {"type: double"}, {"field 'type': 'double' is not supported", "uchar"}},
    {"unknown_encoding", {"encoding: lzma"}, {"field 'encoding': 'lzma'", "raw, gzip"}},
    {"missing_endian", {"type: int16"}, {"field 'endian': missing", "int16"}},
    {"bad_endian", {"type: int16", "endian: middle"}, {"'endian'", "'middle'"}},
    {"missing_data_file", {"data file: not_there.raw"}, {"'data file'", "not_there.raw", "cannot open"}},
    {"short_raw_data", {}, {"'data'", "has 40 bytes, expected 64 bytes"}, DataKind::ShortRaw},
    {"short_gzip_data", {"encoding: gzip"}, {"'data'", "ended after 40 of 64 bytes"}, DataKind::ShortGzip},
    {"truncated_gzip", {"encoding: gzip"}, {"'data'", "ended after", "of 64 bytes"}, DataKind::TruncatedGzip},
    {"corrupt_gzip", {"encoding: gz"}, {"'data'", "gzip/zlib stream is corrupt"}, DataKind::CorruptGzip},
    {"dimension_4", {"dimension: 4", "sizes: 4 4 4 4"}, {"field 'dimension'", "expected 3"}},
    {"duplicate_field", {"+sizes: 4 4 4"}, {"field 'sizes': appears twice (lines 4 and 7)"}},
    {"byte_skip_minus_one", {"byte skip: -1"}, {"field 'byte skip'", "-1", "not supported"}},
    {"direction_none", {"space directions: (1,0,0) none (0,0,1)"}, {"'space directions'", "'none'"}},
    {"spacings_and_directions",
     {"spacings: 1 1 1", "space directions: (1,0,0) (0,1,0) (0,0,1)"},
     {"'spacings'", "'space directions'"}},
    {"line_without_colon", {"+this line has no colon"}, {"line 7", "'field: value'"}},
    {"no_data_anywhere", {"-data file"}, {"'data file'", "missing"}},
    // Sizes that name fewer slices than the data holds would load a wrong cut of it: refused.
    {"sizes_short_of_the_data",
     {"sizes: 4 4 3"},
     {"'data'", "has 64 bytes, expected 48 bytes", "16 trailing bytes, a slice or more"}},
    {"byte_skip_past_the_data",
     {"+byte skip: 32"},
     {"'data'", "has 64 bytes, expected 96 bytes (a 32-byte skip, then 64 bytes of 4x4x4 uint8)"}},
};

class MalformedHeader : public ::testing::TestWithParam<BadHeader> {};

TEST_P(MalformedHeader, ThrowsLoadErrorNamingFileAndField) {
    const BadHeader& c = GetParam();
    const fs::path path = outDir() / (c.name + ".nhdr");
    writeFile(path, editedHeader(c.name, c.edits));
    const std::string gz = gzipBytes(rampBytes(c.data == DataKind::ShortGzip ? 40 : 64));
    std::string data = rampBytes(c.data == DataKind::ShortRaw ? 40 : 64);
    if (c.data == DataKind::ShortGzip) data = gz;
    if (c.data == DataKind::TruncatedGzip) data = gz.substr(0, gz.size() / 2);
    if (c.data == DataKind::CorruptGzip)
        (data = gz)[2] = 7;   // compression method 7 does not exist (deflate is 8)
    writeFile(outDir() / (c.name + ".data"), data);
    expectLoadError(path, c.expect);
}

// Less than a slice after the data (a writer's closing newline) is not an error.
TEST(NrrdLoad, ToleratesTrailingBytesShortOfASlice) {
    writeFile(outDir() / "trailing_newline.nhdr", editedHeader("trailing_newline", {}));
    writeFile(outDir() / "trailing_newline.data", rampBytes(64) + std::string(15, '\n'));
    const Volume v = loadVolume(outDir() / "trailing_newline.nhdr");
    EXPECT_EQ(v.values.size(), 64u);
}

INSTANTIATE_TEST_SUITE_P(VolumeIo, MalformedHeader, ::testing::ValuesIn(kBadHeaders),
                         [](const auto& info) { return info.param.name; });

struct BadFile {
    std::string file;                  // file name; its stem is the test name
    std::string content;               // the file's bytes (gzip-compressed when the name ends in .gz)
    std::vector<std::string> expect;   // substrings of what() besides the file name
};
void PrintTo(const BadFile& b, std::ostream* os) { *os << b.file; }

const BadFile kBadFiles[] = {
    {"wrong_magic.nhdr", "NRRD9\ntype: uint8\n", {"not a NRRD file", "'NRRD9'", "NRRD0001..NRRD0005"}},
    {"binary_junk.nrrd", std::string(100000, '\x01'), {"not a NRRD file"}},
    {"raw_too_short_4x4x4_uint8.raw",
     std::string(60, 'x'),
     {"field 'data': file has 60 bytes, expected 64 bytes"}},
    {"raw_too_long_4x4x4_uint16.raw",
     std::string(130, 'x'),
     {"'data'", "expected 128 bytes", "2 trailing bytes"}},
    {"raw_gzip_too_long_4x4x4_uint8.raw.gz",
     std::string(65, 'x'),
     {"'data'", "more than the expected 64 bytes"}},
    {"raw_gzip_too_short_4x4x4_uint8.raw.gz", std::string(63, 'x'), {"'data'", "ended after 63 of 64 bytes"}},
    {"raw_without_dims.raw", std::string(64, 'x'), {"--raw-dims", "--raw-type"}},
    {"unknown_extension.vti", "<VTKFile/>", {"unknown file type '.vti'", ".nrrd, .nhdr, .mhd, .mha, .nii"}},
};

class MalformedFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(MalformedFile, ThrowsLoadErrorNamingFileAndReason) {
    const BadFile& c = GetParam();
    const fs::path path = outDir() / c.file;
    writeFile(path, path.extension() == ".gz" ? gzipBytes(c.content) : c.content);
    expectLoadError(path, c.expect);
}

INSTANTIATE_TEST_SUITE_P(VolumeIo, MalformedFile, ::testing::ValuesIn(kBadFiles), [](const auto& info) {
    return info.param.file.substr(0, info.param.file.find('.'));
});

TEST(VolumeIoErrors, MissingFileSaysCannotOpen) {
    for (const char* name : {"no_such.nhdr", "no_such_4x4x4_uint8.raw", "no_such.vti"}) {
        const fs::path path = outDir() / name;
        try {
            loadVolume(path);
            FAIL() << "expected LoadError";
        } catch (const LoadError& e) {
            EXPECT_EQ(e.path(), path.string());
            EXPECT_TRUE(contains(e.what(), "cannot open"));
        }
    }
    EXPECT_THROW(loadNrrd(outDir() / "no_such.nhdr"), LoadError);
    EXPECT_THROW(loadRaw(outDir() / "no_such.raw", RawOptions{.dims = {1, 1, 1}}), LoadError);
}

TEST(VolumeIoErrors, RawOptionsAreValidated) {
    writeFile(outDir() / "tiny.raw", rampBytes(8));
    EXPECT_THROW(loadRaw(outDir() / "tiny.raw", RawOptions{.dims = {2, 0, 2}}), LoadError);
    EXPECT_THROW(loadRaw(outDir() / "tiny.raw", RawOptions{.dims = {65536, 65536, 2}}), LoadError);
    EXPECT_THROW(loadRaw(outDir() / "tiny.raw", RawOptions{.dims = {2, 2, 2}, .spacing = {1, -1, 1}}),
                 LoadError);
    EXPECT_EQ(loadRaw(outDir() / "tiny.raw", RawOptions{.dims = {2, 2, 2}}).values.size(), 8u);
}

// == Range and histogram

Volume volumeOf(std::vector<float> values) {
    Volume v;
    v.dims = {int(values.size()), 1, 1};
    v.values = std::move(values);
    updateRange(v);
    return v;
}

TEST(VolumeRange, SkipsNaNAndInfinity) {
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN(),
                    kInf = std::numeric_limits<float>::infinity();
    const Volume v = volumeOf({kNaN, 3.0f, -kInf, 1.0f, kInf, 2.0f});
    EXPECT_EQ(v.range.lo, 1.0f);
    EXPECT_EQ(v.range.hi, 3.0f);
    const Volume allNaN = volumeOf({kNaN, kNaN});
    EXPECT_EQ(allNaN.range.lo, 0.0f);
    EXPECT_EQ(allNaN.range.hi, 0.0f);
    const Volume empty = volumeOf({});
    EXPECT_EQ(empty.range.lo, 0.0f);
    EXPECT_EQ(empty.range.hi, 0.0f);
}

TEST(VolumeHistogram, CountsFiniteValuesInEqualWidthBins) {
    const Volume v = volumeOf({0, 1, 2, 3, 4, 0.5f, std::numeric_limits<float>::quiet_NaN()});
    const Histogram h = computeHistogram(v, 4);   // bins [0,1) [1,2) [2,3) [3,4]
    EXPECT_EQ(h.range.lo, 0.0f);
    EXPECT_EQ(h.range.hi, 4.0f);
    EXPECT_EQ(h.counts, (std::vector<uint64_t>{2, 1, 1, 2}));
    EXPECT_EQ(computeHistogram(volumeOf({5, 5, 5}), 3).counts, (std::vector<uint64_t>{3, 0, 0}));
    EXPECT_THROW(computeHistogram(v, 0), RenderError);
}

TEST(VoxelTypes, NamesAndSizes) {
    EXPECT_STREQ(voxelTypeName(VoxelType::U8), "uint8");
    EXPECT_STREQ(voxelTypeName(VoxelType::U16), "uint16");
    EXPECT_STREQ(voxelTypeName(VoxelType::I16), "int16");
    EXPECT_STREQ(voxelTypeName(VoxelType::F32), "float32");
    EXPECT_EQ(voxelTypeBytes(VoxelType::U8), 1u);
    EXPECT_EQ(voxelTypeBytes(VoxelType::I16), 2u);
    EXPECT_EQ(voxelTypeBytes(VoxelType::F32), 4u);
}

// == Procedural volumes

TEST(Procedural, CheckerboardAlternatesCells) {
    const Volume v = makeCheckerboard({10, 6, 5}, 2);
    EXPECT_EQ(v.name, "checkerboard");
    EXPECT_EQ(v.type, VoxelType::F32);
    for (int z = 0; z < 5; ++z)
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 10; ++x) ASSERT_EQ(v.at(x, y, z), float((x / 2 + y / 2 + z / 2) % 2));
    EXPECT_EQ(v.range.lo, 0.0f);
    EXPECT_EQ(v.range.hi, 1.0f);
    EXPECT_THROW(makeCheckerboard({4, 4, 4}, 0), RenderError);
}

TEST(Procedural, MarschnerLobbStaysInUnitRangeAndMatchesClosedFormAtCentre) {
    const int n = 41;
    const Volume v = makeMarschnerLobb(n);
    EXPECT_EQ(v.name, "marschner-lobb");
    EXPECT_GE(v.range.lo, 0.0f);
    EXPECT_LE(v.range.hi, 1.0f);
    // At (0,0,0): rho_r(0) = cos(2 pi 6 cos 0) = 1, so rho = (1 - 0 + 0.25 * 2) / (2 * 1.25) = 0.6.
    EXPECT_NEAR(v.at(n / 2, n / 2, n / 2), 0.6, 1e-6);
    // A corner, (-1,-1,-1): r = sqrt 2, rho_r = cos(12 pi cos(pi sqrt2 / 2)).
    const double pi = std::numbers::pi;
    const double rhoR = std::cos(12 * pi * std::cos(pi * std::sqrt(2.0) / 2));
    EXPECT_NEAR(v.at(0, 0, 0), (1 + 1 + 0.25 * (1 + rhoR)) / 2.5, 1e-6);
}

TEST(Procedural, SphereShellsAreSymmetric) {
    const int n = 33;
    const Volume v = makeSphereShells(n, 6.0, 2.0);
    EXPECT_EQ(v.name, "sphere-shells");
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const float value = v.at(x, y, z);
                ASSERT_EQ(value, v.at(n - 1 - x, y, z));
                ASSERT_EQ(value, v.at(x, n - 1 - y, z));
                ASSERT_EQ(value, v.at(x, y, n - 1 - z));
                ASSERT_EQ(value, v.at(y, z, x));
            }
    EXPECT_EQ(v.at(16, 16, 22), 1.0f);   // distance 6: on a shell
    EXPECT_EQ(v.at(16, 16, 19), 0.0f);   // distance 3: half way between shells
    EXPECT_EQ(v.at(16, 16, 16), 1.0f);   // the centre is the shell of radius 0
}

} // namespace

// A header may claim more voxels than the machine can hold as floats, behind a small compressed stream
// (audit: a 610 KB .raw.gz took 4.8 GiB). The claim is checked against the memory budget before anything
// is allocated or decompressed, and refused at once naming the file, the claim and the budget.
TEST(VolumeMemoryBudget, AClaimOverTheBudgetIsRefusedAtOnceNamingFileClaimAndBudget) {
    const std::string zeros(size_t(64) * 64 * 128 * 4, '\0');   // float32: 2 MiB
    const fs::path nrrd = outDir() / "budget_f32.nrrd";
    writeFile(nrrd, "NRRD0004\ntype: float\ndimension: 3\nsizes: 64 64 128\nendian: little\nencoding: gzip\n\n" +
                        gzipBytes(zeros));
    EXPECT_EQ(loadVolume(nrrd).voxelCount(), size_t(64) * 64 * 128) << "within the default budget it loads";

    std::optional<testing_support::ScopedEnv> budget(std::in_place, "SPLATLAB_MEMORY_BUDGET_MB", "1");
    const auto t0 = std::chrono::steady_clock::now();
    std::string error;
    try {
        loadVolume(nrrd);
    } catch (const LoadError& e) {
        error = e.what();
    }
    // A raw name claiming 2^31 voxels behind 4 KB of gzip: also refused before any byte is decoded.
    const fs::path bomb = outDir() / "bomb_2048x1024x1024_uint8.raw.gz";
    writeFile(bomb, gzipBytes(std::string(4096, '\0')));
    EXPECT_THROW(loadVolume(bomb), LoadError);
    budget.reset();
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
    EXPECT_NE(error.find(nrrd.string()), std::string::npos) << error;
    EXPECT_NE(error.find("64 x 64 x 128 voxels need 2 MiB"), std::string::npos) << error;
    EXPECT_NE(error.find("memory budget of 1 MiB"), std::string::npos) << error;
    EXPECT_GT(volumeMemoryBudget(), uint64_t(1) << 20) << "the default is half of what the process may use";
}
