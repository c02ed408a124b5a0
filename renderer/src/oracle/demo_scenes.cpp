// Demo scenes (demo_scenes.h): the hard cases at scale 4, and the grazing board at the size of 000 fig. 8.
#include "renderer/oracle/demo_scenes.h"

#include "renderer/errors.h"
#include "renderer/oracle/accuracy.h"
#include "renderer/oracle/hard_cases.h"

#include <algorithm>

namespace renderer {

namespace {

constexpr const char* kPrefix = "scene:";
// The hard cases' volumes grow with the scale: 4 gives 40-64 voxels a side (the board 256), enough to
// see each regime at an editor's viewport and still open at once.
constexpr int kHardCaseScale = 4;
constexpr int kBoard = 512;

} // namespace

const std::vector<DemoSceneInfo>& demoSceneList() {
    // In the order of hardCases(); a test checks that the two lists name the same cases.
    static const std::vector<DemoSceneInfo> list{
        {"near-plane", "The camera inside shells: the kernels at the eye are integrated along the rays (the "
                       "near layer, counted in Stats), the rest splatted; compare the filters at the edges"},
        {"far-away", "A volume a few pixels across: orbit it; reconstruction-only lets sub-pixel splats "
                     "flicker, EWA and low-pass keep a steady blob (adaptive's heatmap: minified, green)"},
        {"grazing-checkerboard", "000 fig. 8 small: near rows magnified, far rows minified; moire at the top "
                                 "with reconstruction only, blur at the bottom with low-pass only"},
        {"anisotropic-1-100", "Spacing 1:1:100: needle-like kernels whose footprints EWA follows as they turn"},
        {"zebra", "Stripes at the grid's highest frequency, minified (001 fig. 8): reconstruction-only aliases "
                  "them into bands, EWA greys them out as a low-pass should"},
        {"marschner-lobb", "The standard reconstruction test: its ripples change shape with the kernel scale "
                           "and the filter"},
        {"huge-coordinates", "Marschner-Lobb 1e6 units from the origin: the image should equal the plain one; "
                             "single-precision error would shake it"},
        {"fov-1", "A 1 degree field of view: nearly parallel rays, as the orthographic scene"},
        {"fov-170", "A 170 degree field of view: footprints stretch towards the image's edges"},
        {"orthographic", "Parallel projection: every footprint has one shape, so one filter fits all"},
        {"thin-slices", "48 slices of 1 % opacity each: a smooth grey with no banding tests the accumulation's "
                        "precision"},
        {"nan-inf-values", "Every 7th voxel NaN, every 11th +Inf: skipped, not spread (no specks)"},
        {"constant-volume", "Every voxel one value: a uniform cube with no seams between kernels"},
        {"one-voxel", "A single kernel: dolly in and out (mouse wheel) with Filter adaptive and watch its "
                      "footprint change filter in the heatmap"},
        {"board-512", "000 fig. 8 at full size, a 512x512x3 board from just above its near edge: with Filter "
                      "adaptive and the heatmap, near rows take reconstruction only (red), far rows EWA (blue); "
                      "minified rows (green) need the paper's 64-px-tall image (docs/accuracy.md)"},
    };
    return list;
}

bool isDemoScene(const std::string& name) {
    const auto& list = demoSceneList();
    return std::any_of(list.begin(), list.end(), [&](const DemoSceneInfo& s) { return s.name == name; });
}

std::string demoSceneNames() {
    std::string names;
    for (const DemoSceneInfo& s : demoSceneList()) names += (names.empty() ? "" : ", ") + s.name;
    return names;
}

DemoScene demoScene(const std::string& name, int heightPx) {
    const auto& list = demoSceneList();
    const auto info = std::find_if(list.begin(), list.end(), [&](const DemoSceneInfo& s) { return s.name == name; });
    if (info == list.end())
        throw LoadError(demoScenePath(name).string(), "scene", "one of the demo scenes: " + demoSceneNames());
    DemoScene scene;
    scene.info = *info;
    if (name == "board-512") {
        const int height = std::max(heightPx, 1);
        ViewedVolume board = grazingCheckerboard(kBoard, kBoard / 64, height, height);
        scene.volume = std::move(board.volume);
        scene.tf = std::move(board.tf);
        scene.camera = board.camera;
    } else {
        for (HardCase& c : hardCases(kHardCaseScale, name)) {
            scene.volume = std::move(c.volume);
            scene.tf = std::move(c.tf);
            scene.camera = c.camera;
        }
        // The case looks along the stripes' normal (it tests compositing along a ray); a class sees them
        // from the side.
        if (name == "zebra") scene.camera.azimuthDeg = 60.0;
    }
    scene.volume.name = name;
    scene.tf.name = name;
    return scene;
}

std::optional<std::string> demoSceneOfPath(const std::filesystem::path& path) {
    const std::string text = path.string();
    if (text.rfind(kPrefix, 0) != 0) return std::nullopt;
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) return std::nullopt; // a file really called so
    return text.substr(std::string(kPrefix).size());
}

std::filesystem::path demoScenePath(const std::string& name) { return kPrefix + name; }

Volume loadVolumeOrScene(const std::filesystem::path& path, const std::optional<RawOptions>& raw,
                         const ProgressCallback& progress) {
    if (const std::optional<std::string> name = demoSceneOfPath(path)) return demoScene(*name, 512).volume;
    return loadVolumeInWorldFrame(path, raw, progress);
}

} // namespace renderer
