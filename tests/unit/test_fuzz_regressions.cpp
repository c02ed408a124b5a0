// Replays tests/fuzz/regressions/<parser>/*: inputs that once crashed, hung or blew up a loader under
// libFuzzer. Each must now load or give a LoadError, quickly; CI runs this without clang.
#include "renderer/errors.h"
#include "renderer/io/volume_io.h"
#include "test_paths.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <map>
#include <string>

using namespace renderer;
namespace fs = std::filesystem;

namespace {

fs::path regressionDir() {
    return testing_support::assetDir().parent_path() / "tests" / "fuzz" / "regressions";
}

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Loads `input` the way the parser's fuzz target does (see tests/fuzz/fuzz_<parser>.cpp).
void loadAsFuzzTargetDoes(const std::string& parser, const fs::path& input, const fs::path& scratch) {
    using Load = std::function<Volume(const fs::path&)>;
    static const std::map<std::string, std::pair<const char*, Load>> kLoaders = {
        {"nrrd", {"fuzz.nrrd", [](const fs::path& p) { return loadNrrd(p); }}},
        {"metaimage", {"fuzz.mha", [](const fs::path& p) { return loadMetaImage(p); }}},
        {"nifti", {"fuzz.nii", [](const fs::path& p) { return loadNifti(p); }}},
        {"slc", {"fuzz.slc", [](const fs::path& p) { return loadSlc(p); }}},
        {"dat", {"fuzz.dat", [](const fs::path& p) { return loadDat(p); }}},
        {"stack", {"fuzz.tif", [](const fs::path& p) { return loadImageStack(p); }}},
    };
    const std::string bytes = readFile(input);
    if (parser == "raw_name") {
        const size_t newline = bytes.find('\n');
        const std::string name = bytes.substr(0, newline);
        const auto options = rawOptionsFromFileName(name);
        if (!options) return;
        std::ofstream(scratch / name, std::ios::binary)
            << (newline == std::string::npos ? "" : bytes.substr(newline + 1));
        loadRaw(scratch / name, *options);
        return;
    }
    const auto it = kLoaders.find(parser);
    ASSERT_NE(it, kLoaders.end()) << "unknown parser folder " << parser;
    std::ofstream(scratch / it->second.first, std::ios::binary) << bytes;
    it->second.second(scratch / it->second.first);
}

TEST(FuzzRegressions, EveryInputLoadsOrGivesALoadErrorQuickly) {
    ASSERT_TRUE(fs::is_directory(regressionDir())) << regressionDir();
    int replayed = 0;
    for (const auto& parserDir : fs::directory_iterator(regressionDir())) {
        if (!parserDir.is_directory()) continue;
        const std::string parser = parserDir.path().filename().string();
        const fs::path scratch = testing_support::testOutputDir() / "fuzz_regressions" / parser;
        fs::create_directories(scratch);
        // A detached header in the corpus may name "data.raw", as the fuzz targets provide one.
        {
            std::ofstream data(scratch / "data.raw", std::ios::binary);
            for (int i = 0; i < 4096; ++i)
                data.put(char(i * 7 % 251));
        }
        for (const auto& input : fs::directory_iterator(parserDir.path())) {
            SCOPED_TRACE(input.path().string());
            const auto t0 = std::chrono::steady_clock::now();
            try {
                loadAsFuzzTargetDoes(parser, input.path(), scratch);
            } catch (const LoadError& e) {
                EXPECT_NE(std::string(e.what()).find(": "), std::string::npos);
            }
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            EXPECT_LT(seconds, 5.0) << "slow input"; // each took well under 0.1 s after its fix (ASan)
            ++replayed;
        }
    }
    EXPECT_GE(replayed, 2);
}

} // namespace
