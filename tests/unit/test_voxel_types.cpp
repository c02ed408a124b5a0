// Volumes keep their file's voxel type (voxel_values.h): a uint8 scan takes a byte a voxel from the
// reader to the scene builder, and everything computed from the values (range, histogram, percentile
// window, classes, gradients) is what the same values as floats give.
#include "renderer/io/volume_io.h"
#include "renderer/model/gradients.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/window.h"
#include "test_paths.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using namespace renderer;
namespace fs = std::filesystem;

namespace {

fs::path outDir() { return testing_support::testOutputDir("voxel_types"); }

// The same values held as floats: what every volume was before it kept its file's type.
Volume asFloats(Volume v) {
    v.values.floats();
    return v;
}

// A 24 x 20 x 16 volume of `T` with a smooth ramp, a bright block and noise: every bucket and
// gradient direction is met.
template <class T> Volume mixedVolume(T lo, T hi, unsigned seed) {
    Volume v;
    v.name = "mixed";
    v.dims = {24, 20, 16};
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> noise(0.0, 0.1);
    std::vector<T> values(v.voxelCount());
    for (int z = 0; z < v.dims.z; ++z)
        for (int y = 0; y < v.dims.y; ++y)
            for (int x = 0; x < v.dims.x; ++x) {
                const double ramp = 0.8 * double(x + y + z) / double(24 + 20 + 16);
                const double block = x > 8 && x < 16 && y > 6 && z > 4 && z < 12 ? 0.2 : 0.0;
                values[v.index(x, y, z)] = T(double(lo) + (double(hi) - double(lo)) * (ramp + block) * (1.0 - noise(random)));
            }
    v.values = std::move(values);
    updateRange(v);
    return v;
}

// Resident memory of this process (VmRSS) or its peak since the last reset (VmHWM), from /proc.
size_t residentBytes(const char* field) {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind(field, 0) == 0) return size_t(std::stoull(line.substr(std::strlen(field) + 1))) * 1024;
    return 0;
}

} // namespace

TEST(VoxelTypes, RawFilesOfEachTypeAreHeldInThatType) {
    struct Case {
        const char* name;
        VoxelType type;
        std::vector<float> values;   // what the file holds, in the data's units
    };
    const std::vector<Case> cases = {
        {"u8_4x2x1_uint8.raw", VoxelType::U8, {0, 1, 2, 127, 128, 200, 254, 255}},
        {"u16_4x2x1_uint16.raw", VoxelType::U16, {0, 1, 255, 256, 4095, 30000, 65534, 65535}},
        {"i16_4x2x1_int16.raw", VoxelType::I16, {-32768, -1024, -1, 0, 1, 40, 3071, 32767}},
        {"f32_4x2x1_float.raw", VoxelType::F32, {-1000.5f, 0, 0.25f, 1e-3f, 3e38f, -3e38f, 7, 8}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        std::string bytes;
        for (float value : c.values) {
            char b[4];
            const size_t n = voxelTypeBytes(c.type);
            if (c.type == VoxelType::U8) b[0] = char(uint8_t(value));
            if (c.type == VoxelType::U16) { const uint16_t u = uint16_t(value); std::memcpy(b, &u, 2); }
            if (c.type == VoxelType::I16) { const int16_t i = int16_t(value); std::memcpy(b, &i, 2); }
            if (c.type == VoxelType::F32) std::memcpy(b, &value, 4);
            bytes.append(b, n);   // little-endian on the machines this runs on (x86-64, arm64)
        }
        ASSERT_TRUE(testing_support::writeFile(outDir() / c.name, bytes));
        const Volume v = loadVolume(outDir() / c.name);
        EXPECT_EQ(v.values.type(), c.type);
        EXPECT_EQ(v.values.bytes(), c.values.size() * voxelTypeBytes(c.type));
        ASSERT_EQ(v.values.size(), c.values.size());
        for (size_t i = 0; i < c.values.size(); ++i) EXPECT_EQ(v.values[i], c.values[i]) << "voxel " << i;
    }
}

// The window's percentiles count integer values instead of sorting a float copy: the same nearest rank.
TEST(VoxelTypes, PercentileWindowOfIntegersIsTheFloatsOne) {
    const std::vector<Volume> volumes = {mixedVolume<uint8_t>(0, 255, 1), mixedVolume<uint16_t>(0, 4095, 2),
                                         mixedVolume<int16_t>(-1024, 3071, 3), mixedVolume<int16_t>(-32768, 32767, 4)};
    for (const Volume& v : volumes) {
        SCOPED_TRACE(voxelTypeName(v.values.type()));
        ASSERT_NE(v.values.type(), VoxelType::F32);
        const Volume f = asFloats(v);
        for (const auto& [lo, hi] : {std::pair{0.0, 100.0}, {1.0, 99.0}, {50.0, 50.0}, {0.1, 99.9}, {37.5, 62.5}}) {
            const ValueRange a = percentileWindow(v, lo, hi), b = percentileWindow(f, lo, hi);
            EXPECT_EQ(a.lo, b.lo) << lo;
            EXPECT_EQ(a.hi, b.hi) << hi;
        }
        EXPECT_EQ(percentileWindow(v, 0, 100).lo, v.range.lo);
        EXPECT_EQ(percentileWindow(v, 0, 100).hi, v.range.hi);
    }
}

// What the renderer is given from the values is the same whatever type holds them.
TEST(VoxelTypes, RangeHistogramClassesAndGradientsMatchTheFloats) {
    const TransferFunction tf = builtinPreset("grey-ramp");
    for (const Volume& v : {mixedVolume<uint8_t>(0, 255, 5), mixedVolume<int16_t>(-1024, 3071, 6)}) {
        SCOPED_TRACE(voxelTypeName(v.values.type()));
        const Volume f = asFloats(v);
        EXPECT_EQ(v.values.bytes() * 4, f.values.bytes() * voxelTypeBytes(v.values.type()));
        Volume ranged = f;
        updateRange(ranged);
        EXPECT_EQ(v.range.lo, ranged.range.lo);
        EXPECT_EQ(v.range.hi, ranged.range.hi);
        EXPECT_EQ(computeHistogram(v, 64).counts, computeHistogram(f, 64).counts);
        const SplatScene a = buildSplatScene(v, tf), b = buildSplatScene(f, tf);
        EXPECT_EQ(a.classes, b.classes);
        EXPECT_EQ(a.lists[2].entries(), b.lists[2].entries());
        const auto ga = computeGradients(v), gb = computeGradients(f);
        ASSERT_TRUE(ga && gb);
        EXPECT_EQ(ga->scale, gb->scale);
        EXPECT_EQ(ga->xyz, gb->xyz);
    }
}

// Opening a uint8 volume (reading it, its range, histogram and percentile window: what `info` and the
// editor do first) takes at most 1.5 times its voxel bytes; as floats it took 4 times and more.
TEST(VoxelTypes, OpeningAUint8VolumeTakesAtMostOneAndAHalfTimesItsBytes) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer's shadow memory and quarantine make resident memory meaningless";
#endif
    const fs::path file = outDir() / "large_512x512x384_uint8.raw";
    const size_t bytes = size_t(512) * 512 * 384;   // 96 MiB
    {
        std::string data(bytes, '\0');
        for (size_t i = 0; i < bytes; ++i) data[i] = char(i * 7 % 251);
        ASSERT_TRUE(testing_support::writeFile(file, data));
    }
    std::ofstream reset("/proc/self/clear_refs");
    reset << "5";   // resets VmHWM to the current VmRSS (Linux 4.0 and later)
    reset.close();
    if (!reset) GTEST_SKIP() << "cannot reset the peak resident memory through /proc/self/clear_refs";
    const size_t before = residentBytes("VmRSS:");
    {
        const Volume v = loadVolume(file);
        const Histogram h = computeHistogram(v, 256);
        const ValueRange w = percentileWindow(v, 1, 99);
        EXPECT_EQ(v.values.bytes(), bytes);
        EXPECT_EQ(v.range.hi, 250.0f);
        EXPECT_GT(w.hi, w.lo);
        EXPECT_EQ(h.counts.size(), 256u);
    }
    const size_t peak = residentBytes("VmHWM:");
    fs::remove(file);
    ASSERT_GT(before, 0u);
    EXPECT_LE(double(peak - before), 1.5 * double(bytes))
        << "peak " << (peak - before) / (1 << 20) << " MiB over the start for " << bytes / (1 << 20) << " MiB of voxels";
}
