// `splatlab report` (see report_command.h): for each scan, 1. the view (framed at --size), 2. the centre
// crop's ground truths, 3. every filter x compositing mode timed and compared (speed_error.h), 4. the
// thumbnails; then the page, written atomically once every scan is measured.
#include "report_command.h"

#include "cli_parse.h"
#include "console_progress.h"
#include "report_page.h"

#include "renderer/errors.h"
#include "renderer/gl/driver_profile.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/image_slabs_gl.h"
#include "renderer/io/atomic_file.h"
#include "renderer/io/volume_io.h"
#include "renderer/model/window.h"
#include "renderer/oracle/demo_scenes.h"
#include "renderer/oracle/speed_error.h"
#include "ui/speed_error_chart.h"

#include <epoxy/gl.h>
#include <sys/utsname.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

namespace {

using namespace renderer;
namespace fs = std::filesystem;

// The preset named like the file ("bonsai" for bonsai.nhdr or bonsai_128x128x128_uint8.raw), else a CT one.
std::string presetFor(const fs::path& volume) {
    const std::string stem = volume.stem().string();
    const std::string name = stem.substr(0, stem.find_first_of("_."));
    const std::vector<std::string> names = builtinPresetNames();
    return std::find(names.begin(), names.end(), name) != names.end() ? name : "ct-skin-bone";
}

// "Linux 6.1.0 x86_64, Intel(R) Xeon(R) ..., 2 threads": what the frame times were measured on.
std::string machineDescription() {
    std::string text;
    if (utsname u{}; uname(&u) == 0) text = std::string(u.sysname) + " " + u.release + " " + u.machine;
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line);)
        if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
            text += ", " + line.substr(line.find(':') + 2);
            break;
        }
    return text + ", " + std::to_string(std::thread::hardware_concurrency()) + " threads";
}

// A file-name-safe form of a setting: "ewa_sheet-front-to-back", "ewa_slabs-0.5-post".
std::string settingFileName(const FilterMeasurement& m) {
    if (m.slabThickness > 0.0) {
        char text[64];
        std::snprintf(text, sizeof text, "_slabs-%g%s", m.slabThickness, m.postClassified ? "-post" : "");
        return filterModeName(m.filter) + std::string(text);
    }
    return std::string(filterModeName(m.filter)) + "_" + compositingName(m.compositing);
}

ReportSection measureScan(SplatRenderer& gl, const ReportArgs& a, const fs::path& volumePath, glm::ivec2 size,
                          Camera camera, const std::string& up, const fs::path& cacheDir, const fs::path& out,
                          const std::string& tag) {
    // 1. The scan classified by its TF and framed at --size; the default settings, unlit.
    const std::string tfSpec = a.tf.empty() ? presetFor(volumePath) : a.tf;
    const Volume volume = loadVolumeOrScene(volumePath);
    const SplatScene scene = buildSplatScene(volume, transferFunctionFromSpec(tfSpec), windowFor(volume, {}));
    ReportSection s;
    s.current.occlusionCulling = driverProfile(glRendererName()).occlusionCulling;
    camera.up = axisFromName(up);
    camera = framedCamera(camera, scene, s.current, size.x, size.y);
    const ImagePlane view = makeImagePlane(camera, scene.centre, scene.radius, size.x, size.y, scene.axes);
    const ImagePlane crop = centreCrop(view, kComparisonCropPx);
    s.name = volumePath.filename().string();
    s.cropWidth = crop.width;
    s.cropHeight = crop.height;
    s.brief = std::to_string(volume.dims.x) + "x" + std::to_string(volume.dims.y) + "x" +
              std::to_string(volume.dims.z) + ", TF " + tfSpec + ", " + std::to_string(size.x) + "x" +
              std::to_string(size.y) + " px";
    s.view = std::to_string(volume.dims.x) + " x " + std::to_string(volume.dims.y) + " x " +
             std::to_string(volume.dims.z) + " voxels at " + std::to_string(size.x) + " x " +
             std::to_string(size.y) + " px, TF " + tfSpec + ", camera " + a.camera + ", up " + up +
             " framed, kernel scale 0.7, density 1, unlit; error over "
             "the centre " +
             std::to_string(crop.width) + " x " + std::to_string(crop.height) + " px";
    // 2. The crop's ground truths (cached), 3. the measurement.
    std::fprintf(stderr, "%s: ground truth of the centre %d x %d px\n", s.name.c_str(), crop.width,
                 crop.height);
    const std::optional<SlabOptions> slabs =
        a.slabThickness > 0.0 ? std::optional(SlabOptions{.thickness = a.slabThickness, .postClassified = a.postClassify})
                              : std::nullopt;
    const CropTruths truths = cropTruths(scene, crop, s.current, {}, cacheDir, printProgress,
                                         slabs && slabs->postClassified);
    gl.setScene(scene);
    s.points = measureSpeedAgainstError(gl, view, crop, truths, s.current, a.repeats);
    Image slabCrop;   // --image-slabs: their row last, in the settings in force
    if (slabs) {
        const ImageSlabsGl pass;
        const auto draw = [&](const ImagePlane& p) { return pass.render(scene, p, s.current, *slabs); };
        s.points.push_back(measureSlabs(draw, view, crop, truths.ofSlabs(*slabs), s.current, *slabs, a.repeats));
        slabCrop = draw(crop);
    }
    // 4. Thumbnails: the view, the crop's truth and each setting's crop.
    s.viewImage = tag + "_view.png";
    gl.render(view, s.current);
    writeImage(gl.readback(), out / s.viewImage);
    s.truthImage = tag + "_truth.png";
    writeImage(truths.attenuating, out / s.truthImage);
    for (const SplatSettings& setting : speedErrorSettings(s.current)) {
        s.cropImages.push_back(tag + "_" + settingFileName(s.points[s.cropImages.size()]) + ".png");
        gl.render(crop, setting);
        writeImage(gl.readback(), out / s.cropImages.back());
    }
    if (slabs) {
        s.cropImages.push_back(tag + "_" + settingFileName(s.points.back()) + ".png");
        writeImage(slabCrop, out / s.cropImages.back());
    }
    for (const FilterMeasurement& m : s.points)
        std::printf("%s | %s | %.3f ms (p10 %.3f, p90 %.3f) | %.3f dB\n", s.name.c_str(), ui::settingLabel(m).c_str(),
                    m.frameMs, m.p10Ms, m.p90Ms, m.psnrDb);
    return s;
}

} // namespace

CLI::App* addReportCommand(CLI::App& app, ReportArgs& a) {
    auto* cmd =
        app.add_subcommand("report", "Speed against error: time every filter x compositing mode on each "
                                     "volume and compare it with the ground truth; write DIR/index.html, DIR/speed.md and DIR/summary.md");
    cmd->add_option("volume", a.volumes, std::string("Volumes: ") + supportedVolumeTypes())->required();
    cmd->add_option("--out", a.out, "Folder for index.html and its thumbnails (created)")->required();
    cmd->add_option("--repeats", a.repeats, "Timed frames per setting (median, p10, p90)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    cmd->add_option("--size", a.size, "View size WxH (errors are over its centre 96 x 96 px)")
        ->capture_default_str();
    cmd->add_option("--camera", a.camera, "azimuth,elevation,distance,fov; then framed")
        ->capture_default_str();
    cmd->add_option("--up", a.up,
                    "Axis of each file's world frame shown upwards (x, y, z, -x, -y, -z): one for every volume, "
                    "or one per volume, comma-separated (bonsai y, headsq -z)")
        ->capture_default_str();
    cmd->add_option("--tf", a.tf,
                    "Transfer function: a preset name or a JSON file (default: the preset named like "
                    "the volume, else ct-skin-bone)");
    cmd->add_option("--cache", a.cache, "Ground-truth cache folder (default: ~/.cache/splatlab/reference)");
    cmd->add_option("--image-slabs", a.slabThickness, "Also time image-aligned slabs this many voxels thick in the "
                                                      "settings in force (GL), their row last")
        ->check(CLI::Range(kMinSlabThickness, kMaxSlabThickness));
    cmd->add_flag("--post-classify", a.postClassify, "With --image-slabs: post-classified, against the "
                                                     "post-classified truth");
    return cmd;
}

int runReport(const ReportArgs& a) {
    const auto t0 = std::chrono::steady_clock::now();
    if (a.postClassify && a.slabThickness == 0.0)
        throw CLI::ValidationError("--post-classify", "applies to image-aligned slabs: give --image-slabs THICKNESS");
    // Every input checked before the first measurement: the volumes exist, the folder takes files.
    const glm::ivec2 size = parseSize(a.size, "--size");
    const Camera camera = parseCamera(a.camera);
    std::vector<std::string> ups;   // each checked here, before anything is measured
    for (size_t at = 0; at <= a.up.size();) {
        const size_t comma = std::min(a.up.find(',', at), a.up.size());
        ups.push_back(a.up.substr(at, comma - at));
        axisFromName(ups.back());
        at = comma + 1;
    }
    if (ups.size() != 1 && ups.size() != a.volumes.size())
        throw CLI::ValidationError("--up", "one axis for every volume or one per volume (" +
                                               std::to_string(a.volumes.size()) + "), not " + std::to_string(ups.size()));
    for (const std::string& v : a.volumes) // a file, a folder of slices, a slice pattern or scene:NAME
        if (!demoSceneOfPath(v) && v.find('%') == std::string::npos && !fs::exists(v))
            throw LoadError(v, "", "no such file (a volume file was expected)");
    const fs::path out = a.out;
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec || !fs::is_directory(out))
        throw LoadError(a.out, "",
                        "cannot create the report folder" + (ec ? " (" + ec.message() + ")" : std::string()));
    checkFileReplaceable(out / "index.html");
    checkFileReplaceable(out / "speed.md");
    checkFileReplaceable(out / "summary.md");
    const fs::path cacheDir = a.cache.empty() ? defaultGroundTruthCacheDir() : fs::path(a.cache);
    auto context = HeadlessGl::create();
    ReportPage page;
    page.glRenderer = glRendererName();
    page.machine = machineDescription();
    page.repeats = a.repeats;
    SplatRenderer gl;
    for (size_t i = 0; i < a.volumes.size(); ++i)
        page.sections.push_back(
            measureScan(gl, a, a.volumes[i], size, camera, ups[ups.size() == 1 ? 0 : i], cacheDir, out,
                        "scan" + std::to_string(i + 1)));
    page.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    writeFileAtomically(out / "index.html", reportHtml(page));
    writeFileAtomically(out / "speed.md", reportMarkdown(page));   // the tables for docs/speed.md
    writeFileAtomically(out / "summary.md", reportSummaryMarkdown(page));   // the README's table
    std::printf("%s: written in %.1f s on %s\n", (out / "index.html").string().c_str(), page.seconds,
                page.glRenderer.c_str());
    return 0;
}
