// Where tests find data: the bundled assets, the shared datasets (optional), and an output folder
// for images written on failure or for a person to look at.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

namespace testing_support {

std::filesystem::path assetDir();                       // SPLATLAB_ASSET_DIR
std::optional<std::filesystem::path> sharedDataDir();   // SPLATLAB_DATA_DIR if it exists
std::filesystem::path testOutputDir();                  // SPLATLAB_TEST_OUT (created)
std::filesystem::path testOutputDir(const std::string& sub);   // a created subfolder of it
// Writes bytes to a file (binary, truncating); returns false when the write failed.
bool writeFile(const std::filesystem::path& path, const std::string& bytes);

} // namespace testing_support

// Skips the current test with a clear message when the shared datasets are absent.
#define SPLATLAB_REQUIRE_SHARED_DATA(var)                                                                  \
    auto var##_opt = testing_support::sharedDataDir();                                                     \
    if (!var##_opt) {                                                                                      \
        GTEST_SKIP() << "shared datasets not found: set SPLATLAB_DATA_DIR to ../shared/data/volumes";     \
    }                                                                                                      \
    const std::filesystem::path var = *var##_opt
