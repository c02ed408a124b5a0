// The ground-truth cache stays within its budget: after each new reference the entries used longest ago
// go first, a cache hit counts as a use, the entry just written stays, and a bad budget is refused.
#include "renderer/errors.h"
#include "renderer/io/image.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/ground_truth_cache.h"
#include "scoped_env.h"
#include "test_paths.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>

using namespace renderer;
using testing_support::ScopedEnv;
namespace fs = std::filesystem;

namespace {

// A file of `bytes` bytes, last used `ageSeconds` ago.
void writeEntry(const fs::path& file, size_t bytes, int ageSeconds) {
    std::ofstream(file, std::ios::binary) << std::string(bytes, 'x');
    fs::last_write_time(file, fs::file_time_type::clock::now() - std::chrono::seconds(ageSeconds));
}

fs::path freshDir(const std::string& name) {
    const fs::path dir = testing_support::testOutputDir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

} // namespace

TEST(GroundTruthCache, PruningRemovesTheEntriesUsedLongestAgoUntilTheRestFit) {
    const fs::path dir = freshDir("gt_cache_prune");
    for (int i = 0; i < 5; ++i) writeEntry(dir / ("e" + std::to_string(i) + ".exr"), 1000, 100 - i);   // e0 oldest
    writeEntry(dir / "notes.txt", 5000, 1000);   // not an entry: never counted or removed
    // 5000 bytes of entries in a budget of 2500, e0 just written: e1, e2 and e3 go (e0 is older, but kept).
    EXPECT_EQ(pruneGroundTruthCache(dir, 2500, dir / "e0.exr"), 3000u);
    EXPECT_TRUE(fs::exists(dir / "e0.exr"));
    for (int i : {1, 2, 3}) EXPECT_FALSE(fs::exists(dir / ("e" + std::to_string(i) + ".exr"))) << i;
    EXPECT_TRUE(fs::exists(dir / "e4.exr"));
    EXPECT_TRUE(fs::exists(dir / "notes.txt"));
    // Within the budget nothing goes; a folder that does not exist prunes nothing and does not throw.
    EXPECT_EQ(pruneGroundTruthCache(dir, 2000, dir / "e0.exr"), 0u);
    EXPECT_EQ(pruneGroundTruthCache(dir / "absent", 0, dir / "e0.exr"), 0u);
}

TEST(GroundTruthCache, ANewReferenceKeepsTheCacheWithinItsBudgetAndAHitCountsAsAUse) {
    const fs::path dir = freshDir("gt_cache_budget");
    const SplatScene scene = buildSplatScene(makeSphereShells(6, 3.0, 1.5), fromSharedPoints("ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {1.0, {1.0, 0.8, 0.3}, 0.9}}));
    const GroundTruthOptions o{.supersample = 1};
    const ImagePlane a = makeImagePlane(Camera{}, scene.centre, scene.radius, 8, 8);
    const ImagePlane b = makeImagePlane(Camera{.azimuthDeg = 40}, scene.centre, scene.radius, 8, 8);
    const ScopedEnv budget("SPLATLAB_CACHE_MAX_MB", "1");
    // Two older entries of 400 KiB: with the first truth (a few KiB) they fit 1 MiB.
    writeEntry(dir / "old1.exr", 400 << 10, 200);
    writeEntry(dir / "old2.exr", 400 << 10, 100);
    cachedGroundTruth(scene, a, SplatSettings{}, o, dir);
    const fs::path entryA = dir / (groundTruthKey(scene, a, SplatSettings{}, o) + ".exr");
    ASSERT_TRUE(fs::exists(entryA));
    EXPECT_TRUE(fs::exists(dir / "old1.exr"));
    // Truth a, written a while ago, is read again (a hit renews it); a third 400 KiB entry arrives, old1
    // is used a second ago, and truth b is computed: the cache is over 1 MiB, and the entry used longest
    // ago, old2, goes.
    fs::last_write_time(entryA, fs::file_time_type::clock::now() - std::chrono::seconds(50));
    writeEntry(dir / "old3.exr", 400 << 10, 10);
    GroundTruthStats hit;
    const Image fromCache = cachedGroundTruth(scene, a, SplatSettings{}, o, dir, {}, &hit);
    ASSERT_TRUE(hit.fromCache);
    EXPECT_GT(fs::last_write_time(entryA), fs::file_time_type::clock::now() - std::chrono::seconds(5))
        << "a hit renews the entry";
    fs::last_write_time(dir / "old1.exr", fs::file_time_type::clock::now() - std::chrono::seconds(1));
    cachedGroundTruth(scene, b, SplatSettings{}, o, dir);
    const fs::path entryB = dir / (groundTruthKey(scene, b, SplatSettings{}, o) + ".exr");
    EXPECT_TRUE(fs::exists(entryB)) << "the entry just written stays";
    EXPECT_FALSE(fs::exists(dir / "old2.exr")) << "used longest ago";
    EXPECT_TRUE(fs::exists(dir / "old1.exr")) << "used a second ago";
    uint64_t total = 0;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".exr") total += e.file_size();
    EXPECT_LE(total, uint64_t(1) << 20);
    EXPECT_EQ(readImage(entryA).rgba, fromCache.rgba) << "renewed by its hit, truth a outlived old2";
}

TEST(GroundTruthCache, ABadBudgetIsRefusedBeforeAnythingIsTraced) {
    EXPECT_EQ(groundTruthCacheBudgetBytes(), kDefaultCacheBudgetMiB << 20);
    for (const char* bad : {"0", "-5", "1.5", "12MB", "lots", " 7", "99999999999999999999"}) {
        const ScopedEnv budget("SPLATLAB_CACHE_MAX_MB", bad);
        try {
            groundTruthCacheBudgetBytes();
            ADD_FAILURE() << bad << " was accepted";
        } catch (const RenderError& e) {
            EXPECT_NE(std::string(e.what()).find("SPLATLAB_CACHE_MAX_MB='" + std::string(bad) + "'"), std::string::npos)
                << e.what();
            EXPECT_NE(std::string(e.what()).find("whole number of MiB"), std::string::npos) << e.what();
        }
    }
    const ScopedEnv budget("SPLATLAB_CACHE_MAX_MB", "64");
    EXPECT_EQ(groundTruthCacheBudgetBytes(), uint64_t(64) << 20);
}
