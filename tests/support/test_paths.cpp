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

bool writeFile(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    return out.good();
}

} // namespace testing_support
