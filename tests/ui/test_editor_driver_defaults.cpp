// The editor starts with the settings the driver's profile chooses (renderer/gl/driver_profile.h) where
// no flag chose: occlusion culling on with llvmpipe, off on a GPU; a flag overrides the driver.
#include "cli_run.h"
#include "scoped_env.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>

TEST(EditorDriverDefaults, OcclusionCullingStartsAsTheDriverSaysUnlessAFlagSays) {
    if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "xvfb-run not found (On Debian/Ubuntu: apt install xvfb xauth)";
    const std::filesystem::path out = testing_support::testOutputDir("editor_driver") / "session.json";
    // The session the editor closes with says whether culling was on; SPLATLAB_DRIVER_PROFILE=gpu gives
    // llvmpipe the GPU's profile.
    auto culling = [&](const char* profile, const std::string& flags) {
        const testing_support::ScopedEnv forced("SPLATLAB_DRIVER_PROFILE", *profile ? profile : nullptr);
        const nlohmann::json s = testing_support::editorClosingSession(
            "\"" + testing_support::headsq() + "\" --up -z " + flags, out);
        EXPECT_TRUE(s.contains("splatting")) << flags;
        return s.value("splatting", nlohmann::json::object()).value("occlusion_culling", false);
    };
    EXPECT_TRUE(culling("", ""));
    EXPECT_FALSE(culling("gpu", ""));
    EXPECT_TRUE(culling("gpu", "--occlusion-culling"));
    EXPECT_FALSE(culling("", "--no-occlusion-culling"));
}
