// `editor --scene NAME` opens each demo scene in its TF and view, and the session it closes with names
// the scene, so that the session opens it again and `render --session` draws it.
#include "cli_run.h"
#include "renderer/oracle/demo_scenes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>

TEST(EditorDemoScenes, EachSceneOpensInItsTfAndViewAndItsSessionOpensItAgain) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path dir = testing_support::testOutputDir("demo_scenes");
    for (const renderer::DemoSceneInfo& info : renderer::demoSceneList()) {
        SCOPED_TRACE(info.name);
        const nlohmann::json s = testing_support::editorClosingSession("--scene " + info.name, dir / (info.name + ".json"));
        ASSERT_TRUE(s.contains("scene")) << "the session names no scene";
        EXPECT_EQ(s["scene"], info.name);
        EXPECT_FALSE(s.contains("volume"));
        const renderer::DemoScene scene = renderer::demoScene(info.name, 100);
        EXPECT_EQ(s["transfer_function"]["name"], info.name);
        EXPECT_EQ(s["transfer_function"]["colour"].size(), scene.tf.colours.size());
        EXPECT_EQ(s["transfer_function"]["opacity"].size(), scene.tf.opacities.size());
        EXPECT_EQ(s["window"]["mode"], "data range");
        EXPECT_DOUBLE_EQ(s["camera"]["azimuth"].get<double>(), scene.camera.azimuthDeg);
        EXPECT_DOUBLE_EQ(s["camera"]["elevation"].get<double>(), scene.camera.elevationDeg);
        EXPECT_DOUBLE_EQ(s["camera"]["distance"].get<double>(), scene.camera.distance);
        EXPECT_DOUBLE_EQ(s["camera"]["fov"].get<double>(), scene.camera.fovYDeg);
        // The board's pan is in pixels of the viewport (545 px tall at 1280x800): placed for its height.
        const double panY = s["camera"]["pan"][1].get<double>();
        if (scene.camera.panPx.y != 0.0) {
            const double heightPx = 100.0 * panY / scene.camera.panPx.y;
            EXPECT_GT(heightPx, 400.0) << "the board's view was placed for an image " << heightPx << " px tall";
            EXPECT_LT(heightPx, 800.0) << "the board's view was placed for an image " << heightPx << " px tall";
        } else {
            EXPECT_EQ(panY, 0.0);
        }
    }
    // The session reopens the scene, in the editor and in `render --session`.
    const nlohmann::json again =
        testing_support::editorClosingSession("--session \"" + (dir / "zebra.json").string() + "\"", dir / "zebra_again.json");
    EXPECT_EQ(again.value("scene", ""), "zebra");
    const std::filesystem::path png = dir / "zebra_render.png";
    std::filesystem::remove(png);
    const std::string render = "env -u DISPLAY LIBGL_ALWAYS_SOFTWARE=1 ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" \"" SPLATLAB_EXE
                               "\" render --session \"" + (dir / "zebra.json").string() + "\" --size 96x64 --out \"" +
                               png.string() + "\" > /dev/null";
    EXPECT_EQ(std::system(render.c_str()), 0) << render;
    EXPECT_TRUE(std::filesystem::exists(png));
}

// The command line says which scenes there are.
TEST(EditorDemoScenes, AnUnknownSceneIsRefusedWithTheNames) {
    const std::filesystem::path log = testing_support::testOutputDir("demo_scenes") / "unknown.log";
    const std::string command = "env -u DISPLAY \"" SPLATLAB_EXE "\" editor --scene zebras > \"" + log.string() + "\" 2>&1";
    EXPECT_NE(std::system(command.c_str()), 0);
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("board-512"), std::string::npos) << text;
}
