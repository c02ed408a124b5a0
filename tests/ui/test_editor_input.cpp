// The editor driven as a user would (xdotool, under its own Xvfb) while every frame takes 2 s: input made
// during slow frames is neither lost nor reinterpreted. scripts/replay_input.sh does the driving; the
// editor writes its session when it closes (--session-out), and the test reads the exact final state.
#include "test_paths.h"

#include "ui/panels.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

// Runs the replay in `mode` into a fresh folder; the session the editor closed with.
nlohmann::json replay(const std::string& mode, std::filesystem::path& out) {
    out = testing_support::testOutputDir() / ("editor_input_" + mode);
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out);
    const std::string script = std::string(SPLATLAB_SOURCE_DIR) + "/tests/ui/scripts/replay_input.sh";
    const std::string command = "LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s \"-screen 0 1280x800x24\" \"" + script +
                                "\" \"" SPLATLAB_EXE "\" \"" + out.string() + "\" " + mode + " > \"" +
                                (out / "replay.log").string() + "\" 2>&1";
    const int status = std::system(command.c_str());
    EXPECT_EQ(status, 0) << "see " << (out / "replay.log") << " and " << (out / "editor.log");
    std::ifstream in(out / "session.json");
    if (!in) return {};
    return nlohmann::json::parse(in);
}

} // namespace

// The same TF point drag, once step by step with pauses and once as one burst of events (press, moves,
// release and the pointer moving on, within one UI frame) followed by a second drag and one Ctrl+Z, ends
// with the same curve: the burst's drag ended where the button was released, and one undo took back one
// gesture. In the burst run a viewport drag turns the camera by exactly its pixels times the orbit gain,
// and Ctrl+A with a typed name replaced the TF panel's file field: Save wrote that file. In both runs the
// fifth point's Opacity slider, dragged past its left end and let go before the pointer moved on to the
// right, ends at exactly 0 (read after the release, it would end at 1).
TEST(EditorInput, SlowFramesNeitherLoseNorReinterpretInput) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1 && command -v xdotool > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run or xdotool not found (On Debian/Ubuntu: apt install xvfb xauth xdotool)";
    std::filesystem::path slowDir, burstDir;
    const nlohmann::json slow = replay("slow", slowDir);
    const nlohmann::json burst = replay("burst", burstDir);
    ASSERT_TRUE(slow.contains("transfer_function") && burst.contains("transfer_function"));

    // The bundled bonsai's preset, with its fourth point raised by the 20 px drag.
    const nlohmann::json& points = slow["transfer_function"]["opacity"];
    ASSERT_EQ(points.size(), 6u);
    EXPECT_GT(points[3]["opacity"].get<double>(), 0.55) << "the slow drag did not move the point";
    EXPECT_EQ(points[4]["opacity"].get<double>(), 0.0) << "the slow slider drag did not end at its left end";
    EXPECT_EQ(burst["transfer_function"]["opacity"][4]["opacity"].get<double>(), 0.0)
        << "the burst's slider drag did not end where the button was released";
    EXPECT_EQ(burst["transfer_function"]["opacity"], points)
        << "the burst's drag, second drag and Ctrl+Z left another curve than the slow drag";

    // 100 px right and 20 px down from the bundled view's azimuth 30, elevation 20.
    EXPECT_NEAR(burst["camera"]["azimuth"].get<double>(), 30.0 - 100.0 * ui::kOrbitDegPerPx, 1e-9);
    EXPECT_NEAR(burst["camera"]["elevation"].get<double>(), 20.0 + 20.0 * ui::kOrbitDegPerPx, 1e-9);
    EXPECT_NEAR(slow["camera"]["azimuth"].get<double>(), 30.0, 1e-9) << "the slow run moved no camera";

    EXPECT_TRUE(std::filesystem::exists(burstDir / "typed_tf.json"))
        << "Ctrl+A and the typed name did not become the TF file's path";
    EXPECT_EQ(burst["transfer_function"]["name"], "typed_tf") << "the TF saved is named after its file";
}
