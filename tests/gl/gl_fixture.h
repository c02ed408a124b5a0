// One headless GL context for the whole gl suite. Without EGL the tests skip with the reason, unless
// REQUIRE_GL=1 (CI), where a skipped GL suite would be a silent failure.
#pragma once
#include "renderer/gl_context.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>

class GlTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (s_context || !s_failure.empty()) return;
        try {
            s_context = renderer::HeadlessGl::create();
        } catch (const std::exception& e) {
            s_failure = e.what();
        }
    }
    void SetUp() override {
        if (!s_failure.empty()) {
            const char* req = std::getenv("REQUIRE_GL");
            if (req && std::string(req) == "1") FAIL() << "REQUIRE_GL=1 but no GL context: " << s_failure;
            GTEST_SKIP() << "no headless GL context: " << s_failure;
        }
        renderer::takeGlErrors();
    }
    // Every GL test ends with KHR_debug silent.
    void TearDown() override {
        if (!s_context) return;
        const auto errors = renderer::takeGlErrors();
        EXPECT_TRUE(errors.empty()) << "KHR_debug reported: " << errors.front();
    }
    static inline std::unique_ptr<renderer::HeadlessGl> s_context;
    static inline std::string s_failure;
};
