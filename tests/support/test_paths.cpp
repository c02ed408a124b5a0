#include "test_paths.h"

#include <cstdlib>
#include <fstream>

namespace testing_support {

static std::filesystem::path envPath(const char* name, const char* fallback) {
    const char* v = std::getenv(name);
    return (v && *v) ? std::filesystem::path(v) : std::filesystem::path(fallback);
}

std::filesystem::path assetDir() { return envPath("SPLATLAB_ASSET_DIR", SPLATLAB_DEFAULT_ASSET_DIR); }

std::optional<std::filesystem::path> sharedDataDir() {
    auto p = envPath("SPLATLAB_DATA_DIR", SPLATLAB_DEFAULT_DATA_DIR);
    if (std::filesystem::is_directory(p)) return p;
    return std::nullopt;
}

std::filesystem::path testOutputDir() {
    auto p = envPath("SPLATLAB_TEST_OUT", SPLATLAB_DEFAULT_TEST_OUT);
    std::filesystem::create_directories(p);
    return p;
}

std::filesystem::path testOutputDir(const std::string& sub) {
    auto p = testOutputDir() / sub;
    std::filesystem::create_directories(p);
    return p;
}

namespace {
// The editor keeps recent files and its layout in SPLATLAB_CONFIG_DIR (ui/file_listing.h): every test
// binary, and the editors it starts, use a folder under the test output instead of the user's, unless
// the variable is set already. Runs before main(), so no test can start an editor first.
[[maybe_unused]] const bool configFolderSet = [] {
    setenv("SPLATLAB_CONFIG_DIR",
           (envPath("SPLATLAB_TEST_OUT", SPLATLAB_DEFAULT_TEST_OUT) / "config").c_str(), 0);
    return true;
}();
} // namespace

bool writeFile(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    return out.good();
}

} // namespace testing_support
