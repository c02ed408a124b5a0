// The splatlab command line: `render` and `info` run headless (EGL, no X server); `editor` opens the
// window. Errors from the renderer become one line on stderr and a non-zero exit.
#include "editor.h"

#include "renderer/camera.h"
#include "renderer/errors.h"
#include "renderer/gl_context.h"
#include "renderer/reference_renderer.h"
#include "renderer/splat_renderer.h"
#include "renderer/volume_io.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>

#include <epoxy/gl.h>

namespace {

using namespace renderer;

std::vector<std::string> splitOn(const std::string& s, char sep) {
    std::vector<std::string> parts;
    std::stringstream in(s);
    for (std::string p; std::getline(in, p, sep);) parts.push_back(p);
    return parts;
}

double parseNumber(const std::string& text, const std::string& flag, const std::string& what) {
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || !std::isfinite(v))
        throw CLI::ValidationError(flag, "'" + text + "' is not a number (" + what + ")");
    return v;
}

glm::ivec2 parseSize(const std::string& text, const std::string& flag) {
    const auto parts = splitOn(text, 'x');
    if (parts.size() != 2) throw CLI::ValidationError(flag, "'" + text + "': expected WxH, e.g. 512x512");
    const int w = int(parseNumber(parts[0], flag, "width")), h = int(parseNumber(parts[1], flag, "height"));
    if (w < 1 || h < 1 || w > 16384 || h > 16384)
        throw CLI::ValidationError(flag, "'" + text + "': width and height must be 1..16384");
    return {w, h};
}

Camera parseCamera(const std::string& text) {
    const auto parts = splitOn(text, ',');
    if (parts.size() != 4)
        throw CLI::ValidationError("--camera", "'" + text + "': expected azimuth,elevation,distance,fov (degrees, "
                                               "bounding radii, degrees), e.g. 30,20,2.5,30");
    Camera c;
    c.azimuthDeg = parseNumber(parts[0], "--camera", "azimuth");
    c.elevationDeg = parseNumber(parts[1], "--camera", "elevation");
    c.distance = parseNumber(parts[2], "--camera", "distance");
    c.fovYDeg = parseNumber(parts[3], "--camera", "fov");
    if (c.elevationDeg < -89.9 || c.elevationDeg > 89.9)
        throw CLI::ValidationError("--camera", "elevation must be within -89.9..89.9 degrees");
    if (!(c.distance > 0)) throw CLI::ValidationError("--camera", "distance must be > 0 (bounding radii)");
    if (!(c.fovYDeg >= 1 && c.fovYDeg <= 170)) throw CLI::ValidationError("--camera", "fov must be 1..170 degrees");
    return c;
}

FilterMode parseFilter(const std::string& s) {
    for (auto m : {FilterMode::Reconstruction, FilterMode::LowPass, FilterMode::Ewa})
        if (s == filterModeName(m)) return m;
    throw CLI::ValidationError("--filter", "'" + s + "': unknown filter (known: reconstruction, low-pass, ewa)");
}

struct RawFlags {
    std::string dims, type, endian = "little";
};

std::optional<RawOptions> rawOptions(const RawFlags& f) {
    if (f.dims.empty() && f.type.empty()) return std::nullopt;
    RawOptions o;
    const auto d = splitOn(f.dims, 'x');
    if (d.size() != 3) throw CLI::ValidationError("--raw-dims", "'" + f.dims + "': expected WxHxD, e.g. 64x64x93");
    for (int i = 0; i < 3; ++i) o.dims[i] = int(parseNumber(d[size_t(i)], "--raw-dims", "a size"));
    const std::pair<const char*, VoxelType> types[] = {
        {"uint8", VoxelType::U8}, {"uint16", VoxelType::U16}, {"int16", VoxelType::I16}, {"float32", VoxelType::F32}};
    bool known = false;
    for (auto [name, t] : types)
        if (f.type == name) o.type = t, known = true;
    if (!known) throw CLI::ValidationError("--raw-type", "'" + f.type + "': expected uint8, uint16, int16 or float32");
    if (f.endian != "little" && f.endian != "big")
        throw CLI::ValidationError("--raw-endian", "'" + f.endian + "': expected little or big");
    o.endian = f.endian == "big" ? Endian::Big : Endian::Little;
    return o;
}

void addRawFlags(CLI::App* cmd, RawFlags& raw) {
    cmd->add_option("--raw-dims", raw.dims, "Dims of a headerless raw file, WxHxD");
    cmd->add_option("--raw-type", raw.type, "Voxel type of a raw file: uint8, uint16, int16, float32");
    cmd->add_option("--raw-endian", raw.endian, "Byte order of a raw file: little or big");
}

int runInfo(const std::string& path, const RawFlags& raw) {
    const Volume v = loadVolume(path, rawOptions(raw));
    std::printf("%s\n", path.c_str());
    std::printf("  dims     %d x %d x %d (%zu voxels)\n", v.dims.x, v.dims.y, v.dims.z, v.voxelCount());
    std::printf("  type     %s\n", voxelTypeName(v.type));
    std::printf("  spacing  %g x %g x %g\n", v.spacing.x, v.spacing.y, v.spacing.z);
    std::printf("  origin   %g, %g, %g\n", v.origin.x, v.origin.y, v.origin.z);
    std::printf("  range    %g .. %g\n", v.range.lo, v.range.hi);
    // Histogram summary: 16 bins, each with its share of voxels and a bar.
    const Histogram h = computeHistogram(v, 16);
    std::printf("  histogram (16 bins)\n");
    const double width = (double(h.range.hi) - h.range.lo) / double(h.counts.size());
    for (size_t i = 0; i < h.counts.size(); ++i) {
        const double share = double(h.counts[i]) / double(std::max<size_t>(v.voxelCount(), 1));
        const int bar = int(std::lround(std::sqrt(share) * 40));   // sqrt: small bins stay visible
        std::printf("  %10.4g .. %-10.4g %6.2f%% %s\n", h.range.lo + width * double(i),
                    h.range.lo + width * double(i + 1), 100.0 * share, std::string(size_t(bar), '#').c_str());
    }
    return 0;
}

struct RenderArgs {
    std::string volume, out, size = "512x512", camera = "30,20,2.5,30", tf = "ct-skin-bone";
    std::string compositing = "splat-every-sample", filter = "ewa", up = "z";
    double kernelScale = SplatSettings{}.kernelScale, density = 1.0;
    int frames = 5;
    bool cpu = false;
    RawFlags raw;
};

int runRender(const RenderArgs& a) {
    const glm::ivec2 size = parseSize(a.size, "--size");
    Camera camera = parseCamera(a.camera);
    camera.up = axisFromName(a.up);
    SplatSettings settings;
    settings.compositing = compositingFromName(a.compositing);
    settings.filter = parseFilter(a.filter);
    if (!(a.kernelScale > 0.05 && a.kernelScale <= 10))
        throw CLI::ValidationError("--kernel-scale", "must be in (0.05, 10] voxel spacings");
    if (!(a.density > 0)) throw CLI::ValidationError("--density", "must be > 0");
    if (a.frames < 1) throw CLI::ValidationError("--frames", "must be >= 1");
    settings.kernelScale = a.kernelScale;
    settings.density = a.density;
    const TransferFunction tf = transferFunctionFromSpec(a.tf);
    const Volume volume = loadVolume(a.volume, rawOptions(a.raw));
    const SplatScene scene = buildSplatScene(volume, tf);
    const ImagePlane plane = makeImagePlane(camera, scene.centre, scene.radius, size.x, size.y);

    Image image;
    std::vector<double> ms;
    std::string device;
    if (a.cpu) {
        device = "CPU oracle (double)";
        for (int i = 0; i < a.frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            image = renderReference(scene, plane, settings);
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
    } else {
        auto context = HeadlessGl::create();
        device = glRendererName();
        SplatRenderer gl;
        gl.setScene(scene);
        gl.render(plane, settings);   // warm-up: shader compilation and first-use costs
        glFinish();
        for (int i = 0; i < a.frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            gl.render(plane, settings);
            glFinish();
            ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        image = gl.readback();
    }
    writeImage(image, a.out);
    std::sort(ms.begin(), ms.end());
    const double median = ms[ms.size() / 2];
    std::printf("%s: %dx%d, %zu splats, %s, %s, %.2f ms/frame (median of %d) on %s\n", a.out.c_str(), size.x,
                size.y, scene.visibleCount(), filterModeName(settings.filter), compositingName(settings.compositing),
                median, a.frames, device.c_str());
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"SplatLab: adaptive EWA volume splatting"};
    app.require_subcommand(0, 1);

    RenderArgs r;
    auto* render = app.add_subcommand("render", "Render a volume headless to an image (PNG, EXR, ...)");
    render->add_option("volume", r.volume, "Volume file (.nrrd, .nhdr, .raw, .raw.gz)")->required();
    render->add_option("--out,-o", r.out, "Output image; .png for people, .exr for float data")->required();
    render->add_option("--size", r.size, "Image size WxH")->capture_default_str();
    render->add_option("--camera", r.camera, "azimuth,elevation,distance,fov (deg, bounding radii, deg)")
        ->capture_default_str();
    render->add_option("--tf", r.tf, "Transfer function: a preset name or a JSON file")->capture_default_str();
    render->add_option("--compositing", r.compositing, "splat-every-sample or xray")->capture_default_str();
    render->add_option("--filter", r.filter, "reconstruction, low-pass or ewa")->capture_default_str();
    render->add_option("--kernel-scale", r.kernelScale, "Reconstruction sigma in voxel spacings")
        ->capture_default_str();
    render->add_option("--density", r.density, "Extinction per voxel length at TF opacity 1")->capture_default_str();
    render->add_option("--frames", r.frames, "Timed frames (the median is printed)")->capture_default_str();
    render->add_option("--up", r.up, "Object axis shown upwards: x, y, z, -x, -y, -z (headsq: -z)")
        ->capture_default_str();
    render->add_flag("--cpu", r.cpu, "Render with the double-precision CPU oracle instead of GL");
    addRawFlags(render, r.raw);

    std::string infoPath;
    RawFlags infoRaw;
    auto* info = app.add_subcommand("info", "Print dims, type, spacing, range and a histogram of a volume");
    info->add_option("volume", infoPath, "Volume file")->required();
    addRawFlags(info, infoRaw);

    EditorOptions e;
    e.volumePath = std::filesystem::path(SPLATLAB_ASSET_DIR) / "volumes" / "headsq.nhdr";
    std::string editorSize = "1280x800", editorVolume, screenshot, editorUp, editorCamera;
    auto* editor = app.add_subcommand("editor", "Open the editor window (default: the bundled headsq)");
    editor->add_option("volume", editorVolume, "Volume file");
    editor->add_option("--tf", e.tfSpec, "Transfer function: a preset name or a JSON file")->capture_default_str();
    editor->add_option("--screenshot", screenshot, "Write a PNG of the window after --frames frames, then exit");
    editor->add_option("--frames", e.frames, "Exit after this many frames (0: run until closed)");
    editor->add_option("--size", editorSize, "Window size WxH")->capture_default_str();
    editor->add_option("--camera", editorCamera, "Starting view: azimuth,elevation,distance,fov");
    editor->add_option("--up", editorUp, "Object axis shown upwards: x, y, z, -x, -y, -z (default: z; "
                                         "-z for the bundled headsq)");

    try {
        app.parse(argc, argv);
        if (*render) return runRender(r);
        if (*info) return runInfo(infoPath, infoRaw);
        // The bundled headsq stores its slices from the crown down, so it is shown with -z up.
        e.upAxis = editorVolume.empty() ? "-z" : "z";
        if (editorVolume.empty()) e.camera = parseCamera("60,15,2.5,30");   // a three-quarter view of the face
        if (!editorCamera.empty()) e.camera = parseCamera(editorCamera);
        if (!editorUp.empty()) e.upAxis = (axisFromName(editorUp), editorUp);
        if (!editorVolume.empty()) e.volumePath = editorVolume;
        if (!screenshot.empty()) e.screenshotPath = screenshot;
        const glm::ivec2 s = parseSize(editorSize, "--size");
        e.width = s.x;
        e.height = s.y;
        if (!screenshot.empty() && e.frames < 1) e.frames = 5;
        return runEditor(e);
    } catch (const CLI::ParseError& err) {
        return app.exit(err);
    } catch (const std::exception& err) {
        std::fprintf(stderr, "splatlab: %s\n", err.what());
        return 1;
    }
}
