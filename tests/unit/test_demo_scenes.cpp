// Demo scenes (renderer/oracle/demo_scenes.h): one for every hard case and the full-size board, each
// with its line of what to look for; opened by name and as "scene:NAME" wherever a volume path goes.
#include "renderer/errors.h"
#include "renderer/oracle/demo_scenes.h"
#include "renderer/oracle/hard_cases.h"
#include "test_paths.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <fstream>

using namespace renderer;

TEST(DemoScenes, EveryHardCaseAndTheBoardOpenByNameWithWhatToLookFor) {
    std::vector<std::string> expected;
    for (const HardCase& c : hardCases(1)) expected.push_back(c.name);
    expected.push_back("board-512");
    std::vector<std::string> names;
    for (const DemoSceneInfo& s : demoSceneList()) {
        names.push_back(s.name);
        EXPECT_GT(s.lookFor.size(), 30u) << s.name << " says too little about what to look for";
        const DemoScene scene = demoScene(s.name, 545);
        EXPECT_GT(scene.volume.voxelCount(), 0u) << s.name;
        EXPECT_EQ(scene.volume.name, s.name);
        EXPECT_GE(scene.tf.colours.size(), 2u) << s.name;
        EXPECT_GE(scene.tf.opacities.size(), 2u) << s.name;
    }
    EXPECT_EQ(names, expected) << "a hard case has no demo scene, or the menu's order differs from hardCases()";
    EXPECT_EQ(demoScene("board-512", 545).volume.dims, glm::ivec3(512, 512, 3));
}

// A demo scene builds only its own case; built alone, each case equals itself built among all.
TEST(DemoScenes, ACaseBuiltAloneEqualsItBuiltAmongAll) {
    for (const HardCase& all : hardCases(1)) {
        const std::vector<HardCase> alone = hardCases(1, all.name);
        ASSERT_EQ(alone.size(), 1u) << all.name;
        EXPECT_EQ(alone[0].volume.dims, all.volume.dims) << all.name;
        EXPECT_EQ(alone[0].volume.spacing, all.volume.spacing) << all.name;
        EXPECT_EQ(alone[0].volume.origin, all.volume.origin) << all.name;
        const auto bits = [](const VoxelValues& values) {   // bits, so NaNs compare equal
            std::vector<uint32_t> out(values.size());
            for (size_t i = 0; i < out.size(); ++i) out[i] = std::bit_cast<uint32_t>(values[i]);
            return out;
        };
        EXPECT_EQ(bits(alone[0].volume.values), bits(all.volume.values)) << all.name;
        EXPECT_EQ(alone[0].camera.distance, all.camera.distance) << all.name;
        EXPECT_EQ(alone[0].tf.opacities.size(), all.tf.opacities.size()) << all.name;
    }
    EXPECT_TRUE(hardCases(1, "no-such-case").empty());
}

// The board's view looks from just above its near edge, panned in pixels: its pan grows with the image.
TEST(DemoScenes, TheBoardsViewIsPannedForTheImagesHeight) {
    const Camera small = demoScene("board-512", 100).camera, tall = demoScene("board-512", 500).camera;
    EXPECT_NE(small.panPx.y, 0.0);
    EXPECT_NEAR(tall.panPx.y, 5.0 * small.panPx.y, 1e-9 * std::abs(tall.panPx.y));
    EXPECT_EQ(tall.distance, small.distance);
}

TEST(DemoScenes, AnUnknownNameIsRefusedWithTheNamesThereAre) {
    try {
        demoScene("zebras", 100);
        FAIL() << "no error";
    } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find("scene:zebras"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("board-512"), std::string::npos) << e.what();
    }
    EXPECT_THROW(loadVolumeOrScene("scene:zebras"), LoadError);
}

TEST(DemoScenes, AScenePathOpensTheSceneUnlessAFileHasThatName) {
    EXPECT_EQ(demoSceneOfPath("scene:zebra"), std::optional<std::string>("zebra"));
    EXPECT_EQ(demoSceneOfPath("zebra.nrrd"), std::nullopt);
    EXPECT_EQ(demoSceneOfPath(demoScenePath("one-voxel")), std::optional<std::string>("one-voxel"));
    EXPECT_EQ(loadVolumeOrScene("scene:zebra").dims, glm::ivec3(64, 64, 64));

    // A file really called "scene:zebra" (a legal name on Linux) is the file.
    const std::filesystem::path before = std::filesystem::current_path();
    std::filesystem::current_path(testing_support::testOutputDir("demo_scene_file"));
    std::ofstream("scene:zebra") << "not a volume";
    EXPECT_EQ(demoSceneOfPath("scene:zebra"), std::nullopt);
    EXPECT_THROW(loadVolumeOrScene("scene:zebra"), LoadError) << "the file, which is no volume, was not read";
    std::filesystem::current_path(before);
}
