// The file browser's logic with no ImGui: which files each path field lists, folders first and by
// name, the recent-files lists and their file, and the config folder's environment variables.
#include "renderer/errors.h"
#include "renderer/io/volume_io.h"
#include "scoped_env.h"
#include "test_paths.h"
#include "ui/file_listing.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <optional>

namespace {

namespace fs = std::filesystem;
using testing::ElementsAre;
using testing::HasSubstr;

std::vector<std::string> names(const ui::FolderListing& listing) {
    std::vector<std::string> out;
    for (const ui::FolderEntry& e : listing.entries)
        out.push_back(e.name + (e.folder ? "/" : ""));
    return out;
}

// A fresh folder with a few files of each kind, a sub-folder and a hidden file.
fs::path sampleFolder() {
    const fs::path dir = testing_support::testOutputDir("file_listing") / "sample";
    fs::remove_all(dir);
    fs::create_directories(dir / "Scans");
    fs::create_directories(dir / "archive");
    for (const char* name : {"head.nhdr", "b.RAW.GZ", "Bone.json", "notes.txt", "view.png", "brain.nii.gz",
                             ".hidden.nrrd", "a.nrrd"})
        std::ofstream(dir / name) << "12345";
    return dir;
}

} // namespace

TEST(FileListing, EachKindMatchesItsOwnFormatsInAnyCase) {
    EXPECT_TRUE(ui::matchesFileKind("HEAD.NII.GZ", ui::FileKind::Volume));
    EXPECT_TRUE(ui::matchesFileKind("x_64x64x93_int16.raw", ui::FileKind::Volume));
    EXPECT_FALSE(ui::matchesFileKind("head.json", ui::FileKind::Volume));
    EXPECT_TRUE(ui::matchesFileKind("bone.json", ui::FileKind::TransferFunction));
    EXPECT_TRUE(ui::matchesFileKind("s.JSON", ui::FileKind::Session));
    EXPECT_TRUE(ui::matchesFileKind("view.exr", ui::FileKind::Image));
    EXPECT_FALSE(ui::matchesFileKind("view.nrrd", ui::FileKind::Image));
    // The volume list is the loaders' own: every extension there names a reader, not "unknown file type".
    const fs::path dir = testing_support::testOutputDir("file_listing");
    for (const std::string& ext : renderer::volumeFileExtensions()) {
        std::ofstream(dir / ("x" + ext)) << "not a volume";
        try {
            renderer::loadVolume(dir / ("x" + ext));
        } catch (const renderer::LoadError& e) {
            EXPECT_THAT(e.what(), testing::Not(HasSubstr("unknown file type"))) << ext;
        }
    }
}

TEST(FileListing, AFolderListsFoldersFirstThenTheFilesOfTheKindByNameIgnoringCase) {
    const fs::path dir = sampleFolder();
    const ui::FolderListing volumes = ui::listFolder(dir, ui::FileKind::Volume);
    EXPECT_TRUE(volumes.error.empty()) << volumes.error;
    EXPECT_EQ(volumes.folder, fs::canonical(dir));
    EXPECT_THAT(names(volumes),
                ElementsAre("archive/", "Scans/", "a.nrrd", "b.RAW.GZ", "brain.nii.gz", "head.nhdr"));
    EXPECT_EQ(volumes.hiddenFiles, 3u); // Bone.json, notes.txt, view.png; the dot file is not counted
    EXPECT_EQ(volumes.entries[2].bytes, 5u);
    EXPECT_THAT(names(ui::listFolder(dir, ui::FileKind::TransferFunction)),
                ElementsAre("archive/", "Scans/", "Bone.json"));
    EXPECT_THAT(names(ui::listFolder(dir, ui::FileKind::Image)),
                ElementsAre("archive/", "Scans/", "view.png"));
    // A relative path with ".." comes back absolute and normalised.
    EXPECT_EQ(ui::listFolder(dir / "Scans" / "..", ui::FileKind::Session).folder, fs::canonical(dir));
}

TEST(FileListing, AFolderThatCannotBeListedSaysWhichAndListsNothing) {
    const fs::path missing = testing_support::testOutputDir("file_listing") / "no_such_folder";
    const ui::FolderListing listing = ui::listFolder(missing, ui::FileKind::Volume);
    EXPECT_TRUE(listing.entries.empty());
    EXPECT_THAT(listing.error, HasSubstr("no_such_folder"));
    EXPECT_THAT(listing.error, HasSubstr("cannot list"));
}

TEST(RecentFiles, NewestFirstWithoutRepeatsAndAtMostTenPerKind) {
    ui::RecentFiles recent;
    const fs::path dir = fs::absolute(testing_support::testOutputDir("file_listing"));
    for (int i = 0; i < 12; ++i)
        ui::addRecentFile(recent, ui::FileKind::Volume, dir / ("v" + std::to_string(i) + ".nrrd"));
    ui::addRecentFile(recent, ui::FileKind::Volume,
                      dir / "sub" / ".." / "v5.nrrd"); // again, spelled otherwise
    const auto& volumes = recent.of(ui::FileKind::Volume);
    ASSERT_EQ(volumes.size(), ui::RecentFiles::kMaxRecent);
    EXPECT_EQ(volumes[0], (dir / "v5.nrrd").string());
    EXPECT_EQ(volumes[1], (dir / "v11.nrrd").string());
    EXPECT_EQ(std::count(volumes.begin(), volumes.end(), (dir / "v5.nrrd").string()), 1);
    EXPECT_EQ(volumes.back(), (dir / "v2.nrrd").string()); // v0 and v1 fell off the end
    EXPECT_TRUE(recent.of(ui::FileKind::Session).empty());
}

TEST(RecentFiles, TheListsRoundTripThroughTheConfigFolderAndABadFileIsNamed) {
    const fs::path config = testing_support::testOutputDir("file_listing") / "config";
    fs::remove_all(config);
    EXPECT_TRUE(ui::loadRecentFiles(config).of(ui::FileKind::Volume).empty()); // none yet: empty, no error
    ui::RecentFiles recent;
    ui::addRecentFile(recent, ui::FileKind::Volume, "/data/head.nhdr");
    ui::addRecentFile(recent, ui::FileKind::TransferFunction, "/tfs/bone.json");
    ui::saveRecentFiles(recent, config); // creates the folder
    const ui::RecentFiles back = ui::loadRecentFiles(config);
    EXPECT_EQ(back.paths, recent.paths);
    EXPECT_FALSE(fs::exists(config / "recent_files.json.tmp"));

    std::ofstream(config / "recent_files.json") << R"({"volume": ["/a.nrrd", 3]})";
    try {
        ui::loadRecentFiles(config);
        ADD_FAILURE() << "a number among the paths must be refused";
    } catch (const renderer::LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr("recent_files.json"));
        EXPECT_THAT(e.what(), HasSubstr("volume"));
    }
    std::ofstream(config / "recent_files.json") << "[not json";
    EXPECT_THROW(ui::loadRecentFiles(config), renderer::LoadError);
}

TEST(RecentFiles, TheConfigFolderComesFromTheEnvironment) {
    using testing_support::ScopedEnv;
    {
        const ScopedEnv config("SPLATLAB_CONFIG_DIR", "/tmp/splatlab_test_config"), xdg("XDG_CONFIG_HOME", "/tmp/xdg");
        EXPECT_EQ(ui::configFolder(), fs::path("/tmp/splatlab_test_config"));
    }
    const ScopedEnv noConfig("SPLATLAB_CONFIG_DIR", nullptr);
    {
        const ScopedEnv xdg("XDG_CONFIG_HOME", "/tmp/xdg");
        EXPECT_EQ(ui::configFolder(), fs::path("/tmp/xdg/splatlab"));
    }
    const ScopedEnv noXdg("XDG_CONFIG_HOME", nullptr), home("HOME", "/home/someone");
    EXPECT_EQ(ui::configFolder(), fs::path("/home/someone/.config/splatlab"));
}
