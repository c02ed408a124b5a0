// Frame time of the GL splatting path on real scans at 512x512, per filter and compositing mode.
// Datasets: the bundled headsq always; bonsai and engine from SPLATLAB_DATA_DIR when it is set.
// Each benchmark times whole frames (render + glFinish) and reports splats/s; the context line names
// GL_RENDERER. On llvmpipe compare modes only as ratios measured in one run.
#include "renderer/camera.h"
#include "renderer/gl_context.h"
#include "renderer/splat_renderer.h"
#include "renderer/volume_io.h"

#include <benchmark/benchmark.h>
#include <epoxy/gl.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>

using namespace renderer;

namespace {

struct Dataset {
    const char* name;
    std::filesystem::path path;
    const char* preset;
};

std::vector<Dataset> datasets() {
    std::vector<Dataset> d;
    const char* dir = std::getenv("SPLATLAB_DATA_DIR");
    if (dir && std::filesystem::is_directory(dir)) {
        d.push_back({"bonsai", std::filesystem::path(dir) / "bonsai.nhdr", "grey-ramp"});
        d.push_back({"engine", std::filesystem::path(dir) / "engine.nhdr", "fire"});
    }
    d.push_back({"headsq", std::filesystem::path(SPLATLAB_ASSET_DIR) / "volumes" / "headsq.nhdr", "ct-skin-bone"});
    return d;
}

std::map<std::string, SplatScene>& scenes() {
    static std::map<std::string, SplatScene> cache;
    return cache;
}

void renderFrames(benchmark::State& state, const Dataset& d, FilterMode filter, Compositing comp) {
    auto& cache = scenes();
    if (!cache.count(d.name)) cache.emplace(d.name, buildSplatScene(loadVolume(d.path), builtinPreset(d.preset)));
    const SplatScene& scene = cache.at(d.name);
    SplatRenderer r;
    r.setScene(scene);
    SplatSettings s;
    s.filter = filter;
    s.compositing = comp;
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, 512, 512);
    r.render(plane, s);   // warm-up
    glFinish();
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        r.render(plane, s);
        glFinish();
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    state.counters["splats"] = double(r.stats().splatsDrawn);
    state.counters["splats_per_s"] =
        benchmark::Counter(double(r.stats().splatsDrawn) * double(state.iterations()), benchmark::Counter::kIsRate);
}

} // namespace

int main(int argc, char** argv) {
    auto gl = HeadlessGl::create();
    benchmark::AddCustomContext("GL_RENDERER", glRendererName());
    benchmark::AddCustomContext("GL_VERSION", glVersionString());
    for (const Dataset& d : datasets())
        for (auto filter : {FilterMode::Ewa, FilterMode::Reconstruction, FilterMode::LowPass})
            for (auto comp : {Compositing::SplatEverySample, Compositing::XRay}) {
                const std::string name = std::string(d.name) + "/" + filterModeName(filter) + "/" + compositingName(comp);
                benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) { renderFrames(st, d, filter, comp); })
                    ->UseManualTime()
                    ->Unit(benchmark::kMillisecond)
                    ->Iterations(5)
                    ->Repetitions(3)
                    ->ReportAggregatesOnly(true);
            }
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
