// interactive/<volume>: the editor as a user meets it. Each row runs `splatlab editor VOLUME
// --measure-interactive N` under its own Xvfb: the editor turns the camera N times and reports, from its
// own clocks, edit to first image and to full frame (medians, p10, p90), the level the first image came
// from, each level's RMSE against the full frame, and its UI frame's times while a render was in flight
// (ui_p95_ms). Google Benchmark runs each row once (the spread is over the editor's N edits).
//   interactive_bench [--edits N] [benchmark flags]
// Volumes: the bundled bonsai and headsq; engine and the 8.7 M-voxel lidc2 chest CT from
// SPLATLAB_DATA_DIR when it is set; the head phantom at N^3 when SPLATLAB_BENCH_PHANTOM=N (written once
// to the temporary folder with `splatlab phantom`).
#include <benchmark/benchmark.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

int gEdits = 10;

struct Volume {
    std::string name;
    std::string args; // the volume and the flags that show it
};

std::string quoted(const std::filesystem::path& p) { return "\"" + p.string() + "\""; }

std::vector<Volume> volumes() {
    const std::filesystem::path assets = SPLATLAB_ASSET_DIR;
    std::vector<Volume> v = {
        {"bonsai", ""}, // the editor's default: the bundled bonsai, framed, lit
        {"headsq", quoted(assets / "volumes" / "headsq.nhdr") + " --tf ct-skin-bone --up -z --fit"},
    };
    if (const char* dir = std::getenv("SPLATLAB_DATA_DIR"); dir && std::filesystem::is_directory(dir)) {
        v.push_back({"engine", quoted(std::filesystem::path(dir) / "engine.nhdr") + " --tf fire --fit"});
        v.push_back({"lidc2_chest_ct", quoted(std::filesystem::path(dir) / "lidc2_chest_ct.nhdr") +
                                           " --tf ct-skin-bone --fit"});
    }
    if (const char* size = std::getenv("SPLATLAB_BENCH_PHANTOM"); size && std::atoi(size) > 0) {
        const std::string n = std::to_string(std::atoi(size));
        const std::filesystem::path file = std::filesystem::temp_directory_path() / ("splatlab_phantom" + n + ".nhdr");
        if (!std::filesystem::exists(file) &&
            std::system(("\"" SPLATLAB_EXE "\" phantom --size " + n + " --out " + quoted(file) + " > /dev/null").c_str()) != 0)
            std::fprintf(stderr, "interactive_bench: could not write %s\n", file.string().c_str());
        else
            v.push_back({"phantom" + n, quoted(file) + " --tf ct-skin-bone --window -1140,2860 --fit"});
    }
    return v;
}

// The editor's "interactive_result key=value ..." line, as numbers (empty when it did not come).
std::map<std::string, double> measure(const Volume& volume, std::string& output) {
    const std::string command = "xvfb-run -a -s \"-screen 0 1280x800x24\" \"" SPLATLAB_EXE "\" editor " + volume.args +
                                " --size 1280x800 --measure-interactive " + std::to_string(gEdits) + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return {};
    std::array<char, 4096> buffer;
    while (size_t n = fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
    pclose(pipe);
    std::map<std::string, double> values;
    const size_t at = output.find("interactive_result ");
    if (at == std::string::npos) return values;
    std::istringstream line(output.substr(at, output.find('\n', at) - at));
    std::string field;
    while (line >> field)
        if (const size_t eq = field.find('='); eq != std::string::npos && field.rfind("volume=", 0) != 0)
            values[field.substr(0, eq)] = std::atof(field.c_str() + eq + 1);
    return values;
}

void interactive(benchmark::State& state, const Volume& volume) {
    for (auto _ : state) {
        std::string output;
        const std::map<std::string, double> values = measure(volume, output);
        if (values.empty()) {
            state.SkipWithError(("the editor gave no result: " + output.substr(0, 400)).c_str());
            return;
        }
        state.SetIterationTime(values.at("first_image_ms") / 1000.0);
        for (const auto& [key, value] : values) state.counters[key] = value;
        std::printf("%s", output.substr(0, output.find("interactive_result")).c_str());
    }
}

} // namespace

int main(int argc, char** argv) {
    for (int i = 1; i + 1 < argc; ++i)
        if (std::string(argv[i]) == "--edits") gEdits = std::max(1, std::atoi(argv[i + 1]));
    for (const Volume& v : volumes())
        benchmark::RegisterBenchmark(("interactive/" + v.name).c_str(), interactive, v)
            ->UseManualTime()
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
}
