// Saving and reading user paths that are not plain files: FIFOs, devices, symlinks, leftovers of a killed
// save, image headers that claim more pixels than the file holds (audit issue 33, items 7 to 10).
#include "renderer/errors.h"
#include "renderer/io/atomic_file.h"
#include "renderer/io/image.h"
#include "renderer/io/json_file.h"
#include "renderer/model/transfer_function.h"
#include "test_paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <fstream>

using namespace renderer;
using testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

fs::path freshDir(const std::string& name) {
    const fs::path dir = testing_support::testOutputDir("file_safety") / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Files in `dir` whose names start with a dot: what a save leaves behind.
int hiddenFiles(const fs::path& dir) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename().string().rfind('.', 0) == 0;
    return n;
}

// A PNG of a few dozen bytes that claims width x height RGBA: the signature, its IHDR, an IDAT of a few
// compressed zero bytes and IEND (the audit's bomb was 74 bytes).
std::string tinyPngClaiming(uint32_t width, uint32_t height) {
    auto be32 = [](uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16 & 255), char(v >> 8 & 255), char(v & 255)};
    };
    auto chunk = [&](const std::string& typeAndData) {
        const uint32_t crc =
            uint32_t(crc32(0, reinterpret_cast<const Bytef*>(typeAndData.data()), uInt(typeAndData.size())));
        return be32(uint32_t(typeAndData.size() - 4)) + typeAndData + be32(crc);
    };
    const std::string zeros(64, '\0');
    std::string deflated(128, '\0');
    uLongf size = deflated.size();
    compress(reinterpret_cast<Bytef*>(deflated.data()), &size, reinterpret_cast<const Bytef*>(zeros.data()),
             uLong(zeros.size()));
    deflated.resize(size);
    return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR" + be32(width) + be32(height) + std::string{8, 6, 0, 0, 0}) +
           chunk("IDAT" + deflated) + chunk("IEND");
}

} // namespace

TEST(FileSafety, SavingOverAFifoIsRefusedAndTheFifoStays) {
    const fs::path dir = freshDir("fifo_save");
    const fs::path fifo = dir / "out.json";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    try {
        writeFileAtomically(fifo, "{}");
        ADD_FAILURE() << "replaced a FIFO";
    } catch (const LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr(fifo.string()));
        EXPECT_THAT(e.what(), HasSubstr("a FIFO"));
    }
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_EQ(hiddenFiles(dir), 0);
    ASSERT_EQ(mkfifo((dir / "image.png").c_str(), 0600), 0);
    EXPECT_THROW(checkImageWritable(dir / "image.png"), LoadError) << "checked before the render, not after";
}

TEST(FileSafety, SavingOverADeviceNodeIsRefused) {
    if (geteuid() != 0) GTEST_SKIP() << "making a device node needs root";
    const fs::path dir = freshDir("device_save");
    const fs::path node = dir / "null.png";
    if (mknod(node.c_str(), S_IFCHR | 0600, makedev(1, 3)) != 0) GTEST_SKIP() << "mknod refused here";
    EXPECT_THROW(checkImageWritable(node), LoadError);
    try {
        writeFileAtomically(node, "x");
        ADD_FAILURE() << "replaced a device node";
    } catch (const LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr("a device"));
    }
    EXPECT_TRUE(fs::is_character_file(node));
}

TEST(FileSafety, SavingThroughASymlinkReplacesItsTargetAndKeepsTheLink) {
    const fs::path dir = freshDir("symlink_save");
    fs::create_directories(dir / "real");
    writeFileAtomically(dir / "real" / "tf.json", "old");
    fs::create_symlink("real/tf.json", dir / "link.json");   // relative, as users make them
    writeFileAtomically(dir / "link.json", "new");
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.json")));
    EXPECT_EQ(readText(dir / "real" / "tf.json"), "new");
    EXPECT_EQ(hiddenFiles(dir / "real") + hiddenFiles(dir), 0);
    // A dangling link: its target is created.
    fs::create_symlink("real/new.json", dir / "dangling.json");
    writeFileAtomically(dir / "dangling.json", "made");
    EXPECT_EQ(readText(dir / "real" / "new.json"), "made");
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "dangling.json")));
}

TEST(FileSafety, AKilledSaveLeavesNothingThatBlocksTheNextAndItsLeftoverIsRemoved) {
    const fs::path dir = freshDir("killed_save");
    const fs::path out = dir / "view.json";
    // What the old fixed temporary name left behind, and a leftover of ours from an hour and more ago.
    writeFileAtomically(dir / "keep.json", "x");
    std::ofstream(out.string() + ".tmp") << "half";
    const fs::path stale = dir / ".view.json.splatlab-0123abcd.tmp";
    std::ofstream(stale) << "half";
    fs::last_write_time(stale, fs::file_time_type::clock::now() - std::chrono::hours(2));
    const fs::path fresh = dir / ".view.json.splatlab-89abcdef.tmp";   // another save, still writing
    std::ofstream(fresh) << "live";

    writeFileAtomically(out, "saved");
    EXPECT_EQ(readText(out), "saved");
    EXPECT_FALSE(fs::exists(stale)) << "the killed save's leftover is removed";
    EXPECT_TRUE(fs::exists(fresh)) << "a save in progress is left alone";
    EXPECT_TRUE(fs::exists(out.string() + ".tmp")) << "a file that is not ours is left alone";
}

TEST(FileSafety, ReadingAFifoAsJsonOrImageFailsAtOnceNamingIt) {
    const fs::path dir = freshDir("fifo_read");
    const fs::path fifo = dir / "session.json";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const auto t0 = std::chrono::steady_clock::now();
    try {
        readJsonFile(fifo, "a session");
        ADD_FAILURE() << "read a FIFO";
    } catch (const LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr(fifo.string()));
        EXPECT_THAT(e.what(), HasSubstr("not a regular file"));
    }
    EXPECT_THROW(loadTransferFunction(fifo), LoadError);
    const fs::path image = dir / "image.png";
    ASSERT_EQ(mkfifo(image.c_str(), 0600), 0);
    EXPECT_THROW(readImage(image), LoadError);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
}

TEST(FileSafety, AnImageHeaderClaimingMorePixelsThanItsFileHoldsIsRefusedBeforeAllocating) {
    const fs::path dir = freshDir("image_bomb");
    for (uint32_t side : {16384u, 60000u}) {
        const fs::path png = dir / ("claims_" + std::to_string(side) + ".png");
        ASSERT_TRUE(testing_support::writeFile(png, tinyPngClaiming(side, side)));
        const auto t0 = std::chrono::steady_clock::now();
        try {
            readImage(png);
            ADD_FAILURE() << "read a " << side << "^2 claim";
        } catch (const LoadError& e) {
            EXPECT_THAT(e.what(), HasSubstr(png.string()));
            EXPECT_THAT(e.what(), HasSubstr(std::to_string(side) + "x" + std::to_string(side)));
        }
        EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(1));
    }
    // A real image of that kind still reads.
    Image small(3, 2);
    writeImage(small, dir / "small.png");
    EXPECT_EQ(readImage(dir / "small.png").width, 3);
}
