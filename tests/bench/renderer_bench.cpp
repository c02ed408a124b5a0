// Frame time of the GL splatting path on real scans at 512x512 (or --resolution WxH), per filter and
// compositing mode, the gain of each culling step and of point sprites, and TF-edit latency against a
// scene rebuild.
// Datasets: the bundled headsq always; bonsai and engine from SPLATLAB_DATA_DIR when it is set; the CT head
// phantom at N^3 when SPLATLAB_BENCH_PHANTOM=N (made in memory, as `splatlab phantom --size N` writes it).
// Each benchmark times whole frames (render + glFinish) and reports splats/s, and beside them the error
// of the view's centre crop against its ground truth (psnr_db, rmse); the context line names GL_RENDERER. On llvmpipe compare modes only as ratios measured in one run.
#include "renderer/math/camera.h"
#include "renderer/oracle/filter_comparison.h"
#include "renderer/gl/gl_context.h"
#include "renderer/model/detail_levels.h"
#include "renderer/model/gradients.h"
#include "renderer/model/phantom.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/math/metrics.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/gl/driver_profile.h"
#include "renderer/gl/image_slabs_gl.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/model/transfer_function.h"
#include "renderer/io/volume_io.h"
#include "renderer/model/window.h"

#include <benchmark/benchmark.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <tuple>

using namespace renderer;

namespace {

struct Dataset {
    std::string name;
    std::filesystem::path path;
    std::string preset;   // a built-in preset name or a TF file
    std::optional<ValueRange> window = std::nullopt;   // none: the data's range
    int phantomSize = 0;                               // > 0: the head phantom at this size^3 instead of a file
};

// The bundled assets: SPLATLAB_ASSET_DIR where set (a copy of the binary run from another checkout, as
// scripts/gpu-bench does), else the source tree it was built from.
std::filesystem::path assetDir() {
    const char* dir = std::getenv("SPLATLAB_ASSET_DIR");
    return dir && *dir ? std::filesystem::path(dir) : std::filesystem::path(SPLATLAB_ASSET_DIR);
}

std::vector<Dataset> datasets() {
    std::vector<Dataset> d;
    const char* dir = std::getenv("SPLATLAB_DATA_DIR");
    if (dir && std::filesystem::is_directory(dir)) {
        d.push_back({"bonsai", std::filesystem::path(dir) / "bonsai.nhdr",
                     (assetDir() / "presets" / "bonsai.json").string()});
        d.push_back({"engine", std::filesystem::path(dir) / "engine.nhdr", "fire"});
    }
    d.push_back({"headsq", assetDir() / "volumes" / "headsq.nhdr", "ct-skin-bone"});
    if (const char* size = std::getenv("SPLATLAB_BENCH_PHANTOM"); size && std::atoi(size) > 0)
        d.push_back({"phantom" + std::to_string(std::atoi(size)), {}, "ct-skin-bone", kPhantomSkinBoneWindow,
                     std::atoi(size)});
    return d;
}

// Image size of every benchmark; --resolution WxH changes it (e.g. 1920x1080 on a GPU).
int gWidth = 512, gHeight = 512;
// Each frame's error against the ground truth (psnr_db, rmse counters); --no-errors skips it.
bool gErrors = true;

std::map<std::string, SplatScene>& scenes() {
    static std::map<std::string, SplatScene> cache;
    return cache;
}

// The density that gives a coarser level's scene the full one's extinction (densityFor), by dataset+level.
std::map<std::string, double>& levelDensityScales() {
    static std::map<std::string, double> scales;
    return scales;
}

// The dataset's scene; with gradients (for shading) when the settings need them. level k > 0: the volume
// halved k times (level 1 is the preview while the view moves), each coarse voxel the mean of its fine
// ones, or with `pickOne` one of them, as the editor's levels of detail take them (Downsample),
// classified over the full volume's window.
const SplatScene& sceneOf(const Dataset& d, bool gradients = false, int level = 0, bool pickOne = false) {
    auto& cache = scenes();
    const std::string key = std::string(d.name) + (gradients ? "+gradients" : "") + "+level" + std::to_string(level) +
                            (pickOne ? "+pick" : "");
    if (!cache.count(key)) {
        const Volume full = d.phantomSize > 0 ? makePhantom({.dims = glm::ivec3(d.phantomSize)}) : loadVolume(d.path);
        Volume volume = full;
        for (int k = 0; k < level; ++k) volume = halfResolution(volume, pickOne ? Downsample::PickOne : Downsample::Mean);
        SplatScene scene = buildSplatScene(volume, transferFunctionFromSpec(d.preset), d.window.value_or(full.range));
        if (gradients) addGradients(scene, *computeGradients(volume));
        levelDensityScales()[d.name + std::to_string(level)] = densityFor(volume, full, 1.0);
        cache.emplace(key, std::move(scene));
    }
    return cache.at(key);
}

// Times whole frames (render + glFinish) of one configuration; one more frame with GPU counters on
// reports what was drawn per filter.
// level k > 0: the volume halved k times, seen from the full scene's camera, with its RMSE against the
// full frame and its error against the full scene's ground truth.
// tune: a change to the renderer itself (one of its setters for comparisons), before the warm-up.
void renderFrames(benchmark::State& state, const Dataset& d, SplatSettings s, Camera camera = {}, int level = 0,
                  const std::function<void(SplatRenderer&)>& tune = {}, bool pickOne = false) {
    const SplatScene& full = sceneOf(d, needsGradients(s));
    const SplatScene& scene = sceneOf(d, needsGradients(s), level, pickOne);
    const ImagePlane plane = makeImagePlane(camera, full.centre, full.radius, gWidth, gHeight);
    std::optional<Image> fullImage;
    const SplatSettings fullSettings = s;   // the truth is the full volume's, at its density
    if (level > 0) {
        SplatRenderer f;
        f.setScene(full);
        f.render(plane, s);
        fullImage = f.readback();
        s.density *= levelDensityScales().at(d.name + std::to_string(level));
    }
    SplatRenderer r;
    if (tune) tune(r);
    r.setScene(scene);
    r.render(plane, s);   // warm-up
    if (fullImage) state.counters["rmse_vs_full"] = compareImages(r.readback(), *fullImage).rmse;
    glFinish();
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        r.render(plane, s);
        glFinish();
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    const int pointSlices = r.stats().pointSlices, quadSlices = r.stats().quadSlices;
    const int readBacks = r.stats().readBacks;   // the last timed frame's waits inside it
    r.collectTimers();   // the last timed frame's GPU time per pass (finished by its glFinish)
    for (int i = 0; i < kGpuPasses; ++i)
        if (const double ms = r.stats().passMs[size_t(i)]; ms > 0.0) {
            std::string name = std::string("ms_") + gpuPassName(GpuPass(i));
            std::replace(name.begin(), name.end(), ' ', '_');
            state.counters[name] = ms;
        }
    s.counters = true;
    r.render(plane, s);
    const SplatCounters& c = r.stats().counters;
    state.counters["splats"] = double(c.drawn);
    state.counters["splats_per_s"] =
        benchmark::Counter(double(c.drawn) * double(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["recon"] = double(c.drawnPerMode[0]);
    state.counters["lowpass"] = double(c.drawnPerMode[1]);
    state.counters["ewa"] = double(c.drawnPerMode[2]);
    state.counters["read_backs"] = readBacks;
    state.counters["point_slices"] = pointSlices;   // rasterised: slices drawn as points, as quads
    state.counters["quad_slices"] = quadSlices;
    state.counters["bytes_per_voxel"] = double(r.sceneBytes()) / double(scene.classes.size());
    state.counters["working_MiB"] = double(r.workingBytes()) / (1024.0 * 1024.0);   // the tiled passes' buffers
    state.counters["fragments"] = double(r.stats().fragments);
    state.counters["occluded"] = double(c.culledOccluded);
    state.counters["tiles"] = r.stats().tiles;
    state.counters["tile_entries"] = double(r.stats().tileEntries);
    // The error beside the speed, as the editor's Measure takes it: the view's centre crop against its
    // ground truth (cached on disk by view and kernels: the first run computes each view's once).
    if (gErrors && hasGroundTruth(s)) {
        s.counters = false;
        const ImagePlane crop = centreCrop(plane, kComparisonCropPx);
        const Image truth = cachedGroundTruth(full, crop, fullSettings, {}, defaultGroundTruthCacheDir());
        const ImageError e = cropError(r, crop, truth, s);
        state.counters["psnr_db"] = e.psnrDb;
        state.counters["rmse"] = e.rmse;
    }
}

// TF edit to finished frame: bucket selection (upload the LUT, render) against rebuilding the scene
// (classify every voxel, build and upload the lists, render), alternating two presets.
void tfEdit(benchmark::State& state, const Dataset& d, bool rebuild, SplatSettings s = {}) {
    const Volume volume = loadVolume(d.path);
    SplatScene scene = buildSplatScene(volume, transferFunctionFromSpec(d.preset));
    SplatRenderer r;
    r.setScene(scene);
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, gWidth, gHeight);
    const TransferFunction tfs[2] = {builtinPreset("ct-bone"), transferFunctionFromSpec(d.preset)};
    int k = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const TransferFunction& tf = tfs[k++ % 2];
        if (rebuild) {
            scene = buildSplatScene(volume, tf);
            r.setScene(scene);
        } else {
            setTransferFunction(scene, tf);
            r.setLut(tfTables(scene));
        }
        r.render(plane, s);
        glFinish();
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
}

// A window edit once its drag settles: every voxel classified again and the three axes' lists rebuilt
// (CPU, all cores), alternating the data range and the 1-99 percentile window. The editor then
// uploads the view's axis and renders, as the TF-edit rebuild above does.
void windowEdit(benchmark::State& state, const Dataset& d) {
    const Volume volume = loadVolume(d.path);
    const TransferFunction tf = transferFunctionFromSpec(d.preset);
    const ValueRange windows[2] = {volume.range, percentileWindow(volume, 1.0, 99.0)};
    int k = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const SplatScene scene = buildSplatScene(volume, tf, windows[k++ % 2]);
        benchmark::DoNotOptimize(scene.lists[0].runs.data());
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    state.counters["voxels_per_s"] =
        benchmark::Counter(double(volume.voxelCount()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

// Turning across a 45-degree diagonal: frames alternating two views 2 degrees apart that straddle it
// (each frame's major axis differs from the last, so it uploads that axis's lists) against two views
// 2 degrees apart on one side of it (nothing uploaded). The difference is what a resident axis costs.
void axisTurn(benchmark::State& state, const Dataset& d, bool across) {
    const SplatScene& scene = sceneOf(d);
    SplatRenderer r;
    r.setScene(scene);
    const double azimuths[2] = {across ? 44.0 : 41.0, across ? 46.0 : 43.0};
    ImagePlane planes[2];
    for (int k = 0; k < 2; ++k)
        planes[k] = makeImagePlane(Camera{.azimuthDeg = azimuths[k]}, scene.centre, scene.radius, gWidth, gHeight);
    r.render(planes[1], SplatSettings{});   // warm-up
    glFinish();
    uint64_t uploaded = 0;
    int k = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        r.render(planes[k++ % 2], SplatSettings{});
        glFinish();
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        uploaded += r.stats().uploadBytes;
    }
    state.counters["upload_MiB"] = double(uploaded) / double(state.iterations()) / (1024.0 * 1024.0);
}

// A far view at the level chooseDetailLevel picks (render --detail-levels 2): its frames as renderFrames
// times them, and counters for the level, its kernels in pixels and the optical mass it changed.
// Image-aligned slabs (renderer/gl/image_slabs_gl.h): whole frames, the CPU's per-kernel set-up and the
// GPU's pass, with the work they do. Pre-classified rows give their error as the others do; the
// post-classified truth of a real scan takes far longer, so post-classified rows give none.
void slabFrames(benchmark::State& state, const Dataset& d, SplatSettings s, SlabOptions options) {
    const SplatScene& scene = sceneOf(d, needsGradients(s));
    const ImagePlane plane = makeImagePlane(Camera{}, scene.centre, scene.radius, gWidth, gHeight);
    const ImageSlabsGl pass;
    SlabCounters work;
    Image image = pass.render(scene, plane, s, options, &work);   // warm-up
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        image = pass.render(scene, plane, s, options, &work);
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    state.counters["splats"] = double(work.splats.drawn);
    state.counters["slabs"] = double(work.slabs);
    state.counters["footprint_pixels"] = double(work.footprintPixels);
    state.counters["slab_writes"] = double(work.slabWrites);
    if (gErrors && !options.postClassified) {
        const ImagePlane crop = centreCrop(plane, kComparisonCropPx);
        const Image truth = cachedGroundTruth(scene, crop, s, {}, defaultGroundTruthCacheDir());
        const ImageError e = compareImages(pass.render(scene, crop, s, options), truth);
        state.counters["psnr_db"] = e.psnrDb;
        state.counters["rmse"] = e.rmse;
    }
}

void chosenLevel(benchmark::State& state, const Dataset& d, const SplatSettings& s, const Camera& camera) {
    const SplatScene& full = sceneOf(d, needsGradients(s));
    const Volume volume = d.phantomSize > 0 ? makePhantom({.dims = glm::ivec3(d.phantomSize)}) : loadVolume(d.path);
    const ImagePlane plane = makeImagePlane(camera, full.centre, full.radius, gWidth, gHeight);
    const DetailLevel chosen = chooseDetailLevel(volume, full, plane, s);
    renderFrames(state, d, s, camera, chosen.level);
    state.counters["level"] = chosen.level;
    state.counters["pixel_level"] = chosen.pixelLevel;
    state.counters["kernel_px"] = chosen.kernelPx;
    state.counters["mass_change"] = chosen.massChange;
    state.counters["refused_mass_change"] = chosen.refusedMassChange;
}

void add(const std::string& name, std::function<void(benchmark::State&)> fn, int iterations = 3) {
    benchmark::RegisterBenchmark(name.c_str(), [fn](benchmark::State& st) { fn(st); })
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(iterations)
        ->Repetitions(3)
        ->ReportAggregatesOnly(true);
}

} // namespace

// The settings a user of this driver starts with: occlusion culling as its profile says (on with
// llvmpipe, off on a GPU); the tiles-(no-)occlusion-culling rows set it either way.
SplatSettings driverDefaults() {
    SplatSettings s;
    s.occlusionCulling = driverProfile(glRendererName()).occlusionCulling;
    return s;
}

// Removes argv[i] .. argv[i + n - 1]: Google Benchmark rejects flags it does not know.
void dropArgs(int& argc, char** argv, int i, int n) {
    for (int j = i; j + n < argc; ++j) argv[j] = argv[j + n];
    argc -= n;
}

// Takes --resolution WxH out of argv.
bool parseResolution(int& argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        std::string value;
        if (a.rfind("--resolution=", 0) == 0) value = a.substr(13);
        else if (a == "--resolution" && i + 1 < argc) value = argv[i + 1];
        else continue;
        if (std::sscanf(value.c_str(), "%dx%d", &gWidth, &gHeight) != 2 || gWidth < 1 || gHeight < 1 ||
            gWidth > 16384 || gHeight > 16384) {
            std::fprintf(stderr, "renderer_bench: --resolution expects WxH (1 to 16384 each), got '%s'\n",
                         value.c_str());
            return false;
        }
        dropArgs(argc, argv, i, a == "--resolution" ? 2 : 1);
        return true;
    }
    return true;
}

// Takes --no-errors out of argv, if there.
void parseNoErrors(int& argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]) == "--no-errors") {
            gErrors = false;
            dropArgs(argc, argv, i, 1);
            return;
        }
}

int main(int argc, char** argv) {
    if (!parseResolution(argc, argv)) return 2;
    parseNoErrors(argc, argv);
    auto gl = HeadlessGl::create();
    benchmark::AddCustomContext("resolution", std::to_string(gWidth) + "x" + std::to_string(gHeight));
    benchmark::AddCustomContext("GL_RENDERER", glRendererName());
    benchmark::AddCustomContext("GL_VERSION", glVersionString());
    for (const Dataset& d : datasets()) {
        const std::string n = d.name;
        for (auto filter : {FilterMode::Ewa, FilterMode::Adaptive, FilterMode::Reconstruction, FilterMode::LowPass})
            for (auto comp : {Compositing::SplatEverySample, Compositing::SheetBackToFront, Compositing::SheetFrontToBack,
                              Compositing::XRay}) {
                SplatSettings s = driverDefaults();
                s.filter = filter;
                s.compositing = comp;
                add(n + "/" + filterModeName(filter) + "/" + compositingName(comp),
                    [=](benchmark::State& st) { renderFrames(st, d, s); });
            }
        // Sheets and X-ray are tiled (auto) in the rows above; here through the rasteriser.
        for (auto filter : {FilterMode::Ewa, FilterMode::Adaptive})
            for (auto comp : {Compositing::SheetBackToFront, Compositing::SheetFrontToBack, Compositing::XRay}) {
                SplatSettings s = driverDefaults();
                s.filter = filter;
                s.compositing = comp;
                s.primitive = SplatSettings::Primitive::Raster;
                add(n + "/" + filterModeName(filter) + "/" + compositingName(comp) + "/raster",
                    [=](benchmark::State& st) { renderFrames(st, d, s); });
            }
        // Tiles front to back: refresh every 8, occlusion culling on and off (the driver picks one for the
        // other rows), no early termination.
        for (auto [name, alpha, refresh, cull] : {std::tuple{"tiles-refresh-8", 0.998, 8, true},
                                                  std::tuple{"tiles-occlusion-culling", 0.998, 0, true},
                                                  std::tuple{"tiles-no-occlusion-culling", 0.998, 0, false},
                                                  std::tuple{"tiles-no-early-termination", 1.0, 0, true}}) {
            SplatSettings s = driverDefaults();
            s.compositing = Compositing::SheetFrontToBack;
            s.primitive = SplatSettings::Primitive::Tiles;
            s.opaqueAlpha = alpha;
            s.opaqueRefreshSlices = refresh;
            s.occlusionCulling = cull;
            add(n + "/ewa/sheet-front-to-back/" + name, [=](benchmark::State& st) { renderFrames(st, d, s); });
        }
        // The tile composite's two layouts, a column or a pixel per invocation (the driver picks one).
        for (auto comp : {Compositing::SheetFrontToBack, Compositing::SheetBackToFront})
            for (auto [view, distance] : {std::pair{"", 2.5}, std::pair{"far/", 8.0}})
                for (bool perPixel : {false, true}) {
                    SplatSettings v = driverDefaults();
                    v.compositing = comp;
                    v.primitive = SplatSettings::Primitive::Tiles;
                    add(n + "/" + view + "ewa/" + compositingName(comp) + "/composite-" + (perPixel ? "pixels" : "columns"),
                        [=](benchmark::State& st) {
                            renderFrames(st, d, v, Camera{.distance = distance}, 0,
                                         [=](SplatRenderer& r) { r.setCompositePerPixel(perPixel); });
                        });
                }
        // Tiled frames that read nothing back while they run (deferred: the lists sized from the frames
        // before) against reading each part's list sizes (checked); the driver picks one.
        for (auto comp : {Compositing::SheetFrontToBack, Compositing::SheetBackToFront, Compositing::XRay})
            for (bool deferred : {true, false}) {
                SplatSettings v = driverDefaults();
                v.compositing = comp;
                v.primitive = SplatSettings::Primitive::Tiles;
                add(n + "/ewa/" + compositingName(comp) + "/lists-" + (deferred ? "deferred" : "checked"),
                    [=](benchmark::State& st) {
                        renderFrames(st, d, v, Camera{}, 0, [=](SplatRenderer& r) { r.setDeferredListChecks(deferred); });
                    });
            }
        // What each culling step and the primitive choice gain, full EWA.
        SplatSettings s = driverDefaults();
        s.primitive = SplatSettings::Primitive::Quads;
        add(n + "/ewa/splat-every-sample/quads", [=](benchmark::State& st) { renderFrames(st, d, s); });
        // Image-aligned slabs against the sheets front to back above: pre-classified 0.5 voxels thick,
        // post-classified 0.25, unshaded and shaded per fragment.
        for (auto [name, options, shading] :
             {std::tuple{"pre-0.5", SlabOptions{0.5}, SplatSettings::Shading::None},
              std::tuple{"post-0.25", SlabOptions{0.25, true}, SplatSettings::Shading::None},
              std::tuple{"post-0.25-shaded", SlabOptions{0.25, true}, SplatSettings::Shading::PerFragment}}) {
            SplatSettings v = driverDefaults();
            v.shading = shading;
            add(n + "/ewa/image-slabs/" + name, [=](benchmark::State& st) { slabFrames(st, d, v, options); }, 1);
        }
        s = driverDefaults();
        s.drawAllBuckets = true;
        add(n + "/ewa/splat-every-sample/all-buckets", [=](benchmark::State& st) { renderFrames(st, d, s); });
        // Early termination and occlusion culling (front to back) against none (splat-every-sample then
        // runs back to front), and how often the opaque pixels are refreshed.
        for (auto comp : {Compositing::SplatEverySample, Compositing::SheetFrontToBack}) {
            s = driverDefaults();
            s.compositing = comp;
            s.primitive = SplatSettings::Primitive::Raster;
            s.opaqueAlpha = 1.0;
            add(n + "/ewa/" + compositingName(comp) + "/no-early-termination",
                [=](benchmark::State& st) { renderFrames(st, d, s); });
        }
        s = driverDefaults();
        s.occlusionCulling = false;
        add(n + "/ewa/splat-every-sample/no-occlusion-culling", [=](benchmark::State& st) { renderFrames(st, d, s); });
        for (int refresh : {2, 4, 16, 32}) {
            s = driverDefaults();
            s.opaqueRefreshSlices = refresh;
            add(n + "/ewa/splat-every-sample/refresh-" + std::to_string(refresh),
                [=](benchmark::State& st) { renderFrames(st, d, s); });
        }
        // Adaptive against full EWA where it can choose: close up (magnified) and far away (minified);
        // splat-every-sample, and the editor's tiled sheets front to back.
        for (auto [view, distance] : {std::pair{"near", 1.2}, std::pair{"far", 8.0}})
            for (auto comp : {Compositing::SplatEverySample, Compositing::SheetFrontToBack})
                for (auto filter : {FilterMode::Ewa, FilterMode::Adaptive}) {
                    SplatSettings v = driverDefaults();
                    v.filter = filter;
                    v.compositing = comp;
                    const std::string suffix = comp == Compositing::SplatEverySample ? "" : "/sheet-front-to-back";
                    add(n + "/" + view + "/" + filterModeName(filter) + suffix,
                        [=](benchmark::State& st) { renderFrames(st, d, v, Camera{.distance = distance}); });
                }
        // The editor's preview while the view moves (tiled sheets front to back, as the editor draws).
        s = driverDefaults();
        s.compositing = Compositing::SheetFrontToBack;
        add(n + "/ewa/sheet-front-to-back/half-resolution",
            [=](benchmark::State& st) { renderFrames(st, d, s, {}, 1); });
        // Levels of detail far away, where footprints shrink under a pixel: the whole volume halved
        // once and twice against full resolution, each against the full volume's ground truth, and the
        // level render --detail-levels chooses (level 1 only from about 15 radii at 512x512).
        for (double distance : {6.0, 8.0, 10.0, 16.0, 24.0}) {
            const std::string row = n + "/levels/far" + std::to_string(int(distance));
            for (int level = 0; level <= (distance > 10.0 ? 1 : 2); ++level)
                add(row + "/level" + std::to_string(level),
                    [=](benchmark::State& st) { renderFrames(st, d, s, Camera{.distance = distance}, level); });
            add(row + "/level1-pick-one",
                [=](benchmark::State& st) { renderFrames(st, d, s, Camera{.distance = distance}, 1, {}, true); });
            add(row + "/chosen", [=](benchmark::State& st) { chosenLevel(st, d, s, Camera{.distance = distance}); });
        }
        // Close up, each slice takes points where its footprints fit, against quads for every slice.
        s = driverDefaults();
        s.primitive = SplatSettings::Primitive::Quads;
        add(n + "/near/ewa/quads", [=](benchmark::State& st) { renderFrames(st, d, s, Camera{.distance = 1.2}); });
        // Shading per splat (record pass or vertex stage) against per fragment, and surface splats;
        // splat-every-sample and the editor's tiled sheets front to back. Then TF edits, both ways.
        for (auto comp : {Compositing::SplatEverySample, Compositing::SheetFrontToBack}) {
            const std::string mode = n + "/ewa/" + compositingName(comp) + "/";
            for (auto [name, shading] : {std::pair{"per-splat", SplatSettings::Shading::PerSplat},
                                         std::pair{"per-fragment", SplatSettings::Shading::PerFragment}}) {
                SplatSettings v = driverDefaults();
                v.compositing = comp;
                v.shading = shading;
                add(mode + "shaded-" + name, [=](benchmark::State& st) { renderFrames(st, d, v); });
            }
            s = driverDefaults();
            s.compositing = comp;
            s.surfaceFlatten = 8.0;
            add(mode + "surface-splats", [=](benchmark::State& st) { renderFrames(st, d, s); });
        }
        for (auto comp : {Compositing::SplatEverySample, Compositing::SheetFrontToBack}) {
            s = driverDefaults();
            s.compositing = comp;
            const std::string row =
                n + "/tf-edit/" + (comp == Compositing::SplatEverySample ? "" : "sheet-front-to-back/");
            add(row + "select-buckets", [=](benchmark::State& st) { tfEdit(st, d, false, s); });
            add(row + "rebuild-scene", [=](benchmark::State& st) { tfEdit(st, d, true, s); }, 2);
        }
        add(n + "/window-edit", [=](benchmark::State& st) { windowEdit(st, d); }, 4);
        add(n + "/turn/same-axis", [=](benchmark::State& st) { axisTurn(st, d, false); }, 4);
        add(n + "/turn/across-axes", [=](benchmark::State& st) { axisTurn(st, d, true); }, 4);
    }
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
