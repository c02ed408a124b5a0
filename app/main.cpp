// The splatlab command line: `render` and `info` run headless (EGL, no X server); `editor` opens the
// window. Errors from the renderer become one line on stderr and a non-zero exit.
#include "accuracy.h"
#include "cli_parse.h"
#include "compare_command.h"
#include "slab_frames.h"
#include "console_progress.h"
#include "editor.h"
#include "far_view_level.h"
#include "info_command.h"
#include "orbit_measure.h"
#include "phantom_command.h"
#include "report_command.h"

#include "renderer/math/camera.h"
#include "renderer/errors.h"
#include "renderer/gl/driver_profile.h"
#include "renderer/gl/gl_context.h"
#include "renderer/model/gradients.h"
#include "renderer/model/paraview_preset.h"
#include "renderer/oracle/demo_scenes.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/image_slabs.h"
#include "renderer/math/metrics.h"
#include "renderer/oracle/near_layer.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/io/atomic_file.h"
#include "renderer/io/volume_io.h"
#include "renderer/model/window.h"
#include "ui/session.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <epoxy/gl.h>

namespace {

using namespace renderer;

// A flag's value through a renderer parser: its RenderError (which lists the known names) becomes an
// error naming the flag.
template <class Parse>
auto flagValue(const char* flag, Parse parse) {
    try {
        return parse();
    } catch (const RenderError& e) {
        throw CLI::ValidationError(flag, e.what());
    }
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

// "data", "p1-99" or "LO,HI" in data units.
WindowSettings parseWindow(const std::string& text) {
    WindowSettings w;
    if (text == "data") return w;
    if (text == "p1-99") return {.mode = WindowMode::Percentile, .custom = {}};
    const auto parts = splitOn(text, ',');
    if (parts.size() != 2)
        throw CLI::ValidationError("--window", "'" + text + "': expected data, p1-99 or LO,HI in data units");
    w.mode = WindowMode::Custom;
    // The window is kept in 32-bit floats, as the voxels are.
    const double lo = parseNumber(parts[0], "--window", "low value"), hi = parseNumber(parts[1], "--window", "high value");
    w.custom = {float(lo), float(hi)};
    if (!std::isfinite(w.custom.lo) || !std::isfinite(w.custom.hi))
        throw CLI::ValidationError("--window", "'" + text + "': LO and HI must be finite 32-bit floats (within +-3.4e38)");
    if (!(w.custom.lo < w.custom.hi))
        throw CLI::ValidationError("--window", "'" + text + "': LO must be below HI" +
                                                   (lo < hi ? " (as 32-bit floats the two are equal)" : ""));
    return w;
}

double msSince(std::chrono::steady_clock::time_point t0);

// The help group of every flag for something a saved session also sets (the camera, the TF, how the
// volume looks and is splatted): beside `--session` each is refused, found by this group.
const char* kSessionSetGroup = "What a session sets";

// Puts the options `cmd` gained since it had `before` of them in kSessionSetGroup.
void sessionSets(CLI::App* cmd, size_t before) {
    const std::vector<CLI::Option*> options = cmd->get_options(std::function<bool(CLI::Option*)>{});
    for (size_t i = before; i < options.size(); ++i) options[i]->group(kSessionSetGroup);
}

// A flag's number, checked against the range a session accepts for its setting (splat_settings.h).
double inRange(double value, const char* flag, SettingRange range, const char* unit = "") {
    if (!range.holds(value)) throw CLI::ValidationError(flag, "must be " + formatRange(range.lo, range.hi) + unit);
    return value;
}

// How the volume looks: the flags `render`, `reference` and the editor share.
struct LookFlags {
    std::string window = "data", shading = "none";
    double kernelScale = SplatSettings{}.kernelScale, cutoff = SplatSettings{}.cutoffSigmas, density = 1.0;
    double surfaceFlatten = 1.0, surfaceGradient = SplatSettings{}.surfaceGradient;
    bool orthographic = false;
};

void addLookFlags(CLI::App* cmd, LookFlags& f) {
    const size_t before = cmd->get_options().size();
    cmd->add_flag("--ortho", f.orthographic, "Parallel projection (framed like the perspective view)");
    cmd->add_option("--window", f.window, "Values mapped onto the TF: data (min..max), p1-99, or LO,HI in data units")
        ->capture_default_str();
    cmd->add_option("--kernel-scale", f.kernelScale, "Reconstruction sigma in voxel spacings")->capture_default_str();
    cmd->add_option("--cutoff", f.cutoff, "Footprints are evaluated out to this many sigmas")->capture_default_str();
    cmd->add_option("--density", f.density, "Extinction per voxel length at TF opacity 1")->capture_default_str();
    cmd->add_option("--shading", f.shading, "Headlight Phong: none, per-splat, per-fragment")->capture_default_str();
    cmd->add_option("--surface", f.surfaceFlatten,
                    "Surface splats: flatten kernels by this factor along strong gradients (1: off)")
        ->capture_default_str();
    cmd->add_option("--surface-gradient", f.surfaceGradient,
                    "Gradient magnitude (fraction of the largest) from which a voxel is a surface splat")
        ->capture_default_str();
    sessionSets(cmd, before);
}

void applyLookFlags(const LookFlags& f, SplatSettings& s) {
    s.kernelScale = inRange(f.kernelScale, "--kernel-scale", kKernelScaleRange, " voxel spacings");
    s.cutoffSigmas = inRange(f.cutoff, "--cutoff", kCutoffRange, " sigmas");
    s.density = inRange(f.density, "--density", kDensityRange);
    s.shading = flagValue("--shading", [&] { return shadingFromName(f.shading); });
    s.surfaceFlatten = inRange(f.surfaceFlatten, "--surface", kSurfaceFlattenRange, " (1: volume kernels)");
    s.surfaceGradient = inRange(f.surfaceGradient, "--surface-gradient", kSurfaceGradientRange);
}

const char* kPrimitiveHelp = "How splats reach pixels: auto (tiles for sheets and X-ray, else raster), raster "
                             "(per slice: points where they fit, else quads), points, quads, or tiles (compute passes; sheets "
                             "and X-ray only)";

// How splats are filtered, composited and culled: the flags `render` and the editor share.
struct SplatFlags {
    // Both start with tiled sheets front to back: the fastest mode on every machine measured, and as close
    // to the ground truth as splat-every-sample.
    std::string compositing = "sheet-front-to-back", filter = "ewa", primitive = "auto";
    double cMin = SplatSettings{}.cMin, cMax = SplatSettings{}.cMax, hysteresis = SplatSettings{}.hysteresis;
    double opaqueAlpha = SplatSettings{}.opaqueAlpha;
    int patchSize = SplatSettings{}.patchSize, opaqueRefresh = SplatSettings{}.opaqueRefreshSlices;
    bool noOcclusionCulling = false, occlusionCulling = false;   // neither: the driver's default
};

void addSplatFlags(CLI::App* cmd, SplatFlags& f) {
    const size_t before = cmd->get_options().size();
    cmd->add_option("--compositing", f.compositing, "splat-every-sample, sheet-back-to-front, sheet-front-to-back, xray")
        ->capture_default_str();
    cmd->add_option("--filter", f.filter, "reconstruction, low-pass, ewa or adaptive")->capture_default_str();
    cmd->add_option("--c-min", f.cMin, "Adaptive: reconstruction only where R_k > 1 px / c_min")->capture_default_str();
    cmd->add_option("--c-max", f.cMax, "Adaptive: low-pass only where R_k < 1 px / c_max (0: the paper's "
                                       "2 max (u0^2 + u1^2 + u2^2) / u2^2, at the image's corner)")->capture_default_str();
    cmd->add_option("--patch-size", f.patchSize, "Adaptive: slice voxels per patch side")->capture_default_str();
    cmd->add_option("--hysteresis", f.hysteresis,
                    "Adaptive: a patch changes filter only when a threshold is crossed by this factor")
        ->capture_default_str();
    cmd->add_option("--opaque-alpha", f.opaqueAlpha,
                    "Front to back, pixels this opaque take no more splats (1: never; splat-every-sample "
                    "then runs back to front)")->capture_default_str();
    cmd->add_option("--opaque-refresh", f.opaqueRefresh,
                    "Slices between refreshes of the opaque pixels (occlusion culling; 0: auto, every slice "
                    "with tiles, every 8 rasterised)")->capture_default_str();
    auto* off = cmd->add_flag("--no-occlusion-culling", f.noOcclusionCulling,
                              "Front to back, keep splats whose tiles or pixels are already opaque (early termination "
                              "still skips those pixels): the default on a GPU, where culling's read-backs cost more "
                              "than it saves");
    cmd->add_flag("--occlusion-culling", f.occlusionCulling,
                  "Front to back, cull splats whose tiles or pixels are already opaque: the default with llvmpipe")
        ->excludes(off);
    cmd->add_option("--primitive", f.primitive, kPrimitiveHelp)->capture_default_str();
    sessionSets(cmd, before);
}

void applySplatFlags(const SplatFlags& f, SplatSettings& s) {
    s.compositing = flagValue("--compositing", [&] { return compositingFromName(f.compositing); });
    s.filter = flagValue("--filter", [&] { return filterModeFromName(f.filter); });
    s.primitive = flagValue("--primitive", [&] { return primitiveFromName(f.primitive); });
    if (s.primitive == SplatSettings::Primitive::Tiles && s.compositing == Compositing::SplatEverySample)
        throw CLI::ValidationError("--primitive", "tiles sum sheets: splat-every-sample needs points or quads "
                                                  "(or --compositing sheet-front-to-back, sheet-back-to-front, xray)");
    s.cMin = inRange(f.cMin, "--c-min", kCMinRange);
    s.cMax = inRange(f.cMax, "--c-max", kCMaxRange, " (0: 2 (1 + tan^2(fovY/2) (1 + (W/H)^2)), the image corner's spread)");
    s.patchSize = int(inRange(f.patchSize, "--patch-size", kPatchSizeRange, " voxels"));
    s.hysteresis = inRange(f.hysteresis, "--hysteresis", kHysteresisRange);
    s.opaqueAlpha = inRange(f.opaqueAlpha, "--opaque-alpha", kOpaqueAlphaRange);
    s.opaqueRefreshSlices = int(inRange(f.opaqueRefresh, "--opaque-refresh", kOpaqueRefreshRange, " slices (0: auto)"));
    if (f.noOcclusionCulling || f.occlusionCulling) s.occlusionCulling = f.occlusionCulling;
}

// Neither culling flag: the driver's profile chooses, once the GL context exists.
bool cullingByDriver(const SplatFlags& f) { return !f.noOcclusionCulling && !f.occlusionCulling; }

// `render --session`, `editor --session`: a flag for what the session sets is an error beside it, not
// silently overridden by the session or overriding it.
void rejectFlagsBesideSession(const CLI::App* cmd) {
    for (const CLI::Option* o : cmd->get_options())
        if (o->get_group() == kSessionSetGroup && o->count() > 0)
            throw CLI::ValidationError(o->get_name(), "not with --session: the session sets it");
}

// What `render` and `reference` share: the volume, the view and how it looks.
struct SceneArgs {
    std::string volume, out, size = "512x512", camera = "30,20,2.5,30", tf = "ct-skin-bone", up = "z";
    std::string session;   // render --session: a saved editor session instead of the flags above
    bool fit = false;
    LookFlags look;
    RawFlags raw;
};

void addSceneOptions(CLI::App* cmd, SceneArgs& a) {
    cmd->add_option("volume", a.volume, std::string("Volume: ") + supportedVolumeTypes())->required();
    cmd->add_option("--out,-o", a.out, "Output image; .png for people, .exr for float data")->required();
    cmd->add_option("--size", a.size, "Image size WxH")->capture_default_str();
    const size_t before = cmd->get_options().size();
    cmd->add_option("--camera", a.camera, "azimuth,elevation,distance,fov (deg, bounding radii, deg)")
        ->capture_default_str();
    cmd->add_option("--up", a.up, "Axis of the file's world frame shown upwards: x, y, z, -x, -y, -z (headsq: -z)")->capture_default_str();
    cmd->add_flag("--fit", a.fit, "Move the camera along its line of sight, and pan, until everything the TF shows "
                                  "fills the image");
    cmd->add_option("--tf", a.tf,
                    "Transfer function: a preset name, a JSON file or a 3D Slicer presets.xml (FILE.xml#NAME "
                    "picks one)")
        ->capture_default_str();
    sessionSets(cmd, before);
    addLookFlags(cmd, a.look);
    addRawFlags(cmd, a.raw);
}

struct Scene {
    SplatScene scene;
    Camera camera;   // the plane's (framed when --fit)
    ImagePlane plane;
    SplatSettings settings;
    std::array<float, 3> background{0.0f, 0.0f, 0.0f};   // behind a PNG: black, or the session's
};

// The volume classified by `tf` over `window`, its gradients when the settings or the TF need them, and
// the view.
// detailLevels > 0: a far view from a coarser level, at most that many halvings (render --detail-levels).
void finishScene(Scene& s, const std::filesystem::path& volumePath, const RawFlags& raw, const TransferFunction& tf,
                 const WindowSettings& window, Camera camera, glm::ivec2 size, bool fit = false, int detailLevels = 0) {
    const Volume volume = loadVolumeOrScene(volumePath, rawOptions(raw));
    if (volume.resampled)
        std::fprintf(stderr,
                     "note: %s: its axes are sheared (not orthogonal); the voxels are resampled (trilinear) onto "
                     "a grid along the world axes, %d x %d x %d at %g x %g x %g (splatlab info prints the "
                     "file's axes)\n",
                     volumePath.string().c_str(), volume.dims.x, volume.dims.y, volume.dims.z, volume.spacing.x,
                     volume.spacing.y, volume.spacing.z);
    s.scene = buildSplatScene(volume, tf, windowFor(volume, window));
    // Shading, surface splats, gradient opacity, the 2D TF.
    if (needsGradients(s.settings) || !tf.gradientOpacity.empty() || !tf.widgets2d.empty()) {
        std::fprintf(stderr, "gradients\n");
        addGradients(s.scene, *computeGradients(volume, printProgress));
    }
    if (fit) camera = framedCamera(camera, s.scene, s.settings, size.x, size.y);
    s.camera = camera;
    s.plane = makeImagePlane(camera, s.scene.centre, s.scene.radius, size.x, size.y, s.scene.axes);
    if (detailLevels > 0) drawFarViewFromLevel(s.scene, s.settings, volume, s.plane, detailLevels);
}

// `render --session FILE`: the view the editor saved (volume, TF, window, camera, every setting,
// background), at --size; a volume argument replaces the session's volume.
Scene buildSessionScene(const SceneArgs& a, int detailLevels) {
    ui::EditorState state;
    std::filesystem::path volume = ui::loadSession(a.session, state);
    if (!a.volume.empty()) volume = a.volume;
    if (volume.empty()) throw LoadError(a.session, "volume", "a volume path (or a volume argument after render)");
    Scene s;
    s.settings = state.settings;
    s.background = state.background;
    finishScene(s, volume, a.raw, state.tf, state.window, state.camera, parseSize(a.size, "--size"), false, detailLevels);
    return s;
}

// The TF a --tf spec names; what an import leaves out (a Slicer preset's gradient opacity) goes to stderr.
TransferFunction tfFromSpecNoting(const std::string& spec) {
    std::vector<std::string> notes;
    TransferFunction tf = transferFunctionFromSpec(spec, &notes);
    for (const std::string& note : notes)
        std::fprintf(stderr, "splatlab: note: %s\n", note.c_str());
    return tf;
}

Scene buildScene(const SceneArgs& a, const SplatFlags& splat, int detailLevels = 0) {
    if (!a.session.empty()) return buildSessionScene(a, detailLevels);
    if (a.volume.empty()) throw CLI::ValidationError("volume", "a volume file is required (or --session FILE)");
    const glm::ivec2 size = parseSize(a.size, "--size");
    Camera camera = parseCamera(a.camera);
    camera.up = axisFromName(a.up);
    camera.orthographic = a.look.orthographic;
    Scene s;
    applyLookFlags(a.look, s.settings);
    applySplatFlags(splat, s.settings);
    finishScene(s, a.volume, a.raw, tfFromSpecNoting(a.tf), parseWindow(a.look.window), camera, size, a.fit, detailLevels);
    return s;
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// What only `render` sets: its outputs and how it runs.
struct RenderArgs {
    int frames = 5, detailLevels = 0;
    bool cpu = false, counters = false;
    SlabOptions slabs{.thickness = 0.0};   // --image-slabs (0: the volume's own sheets), --post-classify, --supersample
    std::string heatmap;
    double orbitStep = std::nan("");   // --orbit: the turn's step in degrees (NaN: no orbit)
    std::string orbitCsv;
    SplatFlags splat;
};

void printCounters(const SplatCounters& c) {
    using ull = unsigned long long;
    // Every splat past the transparent and near-plane culls has its footprint (or, culled as hidden, the
    // bound the occlusion test projects) computed: what a hidden voxel still costs.
    const uint64_t computed = c.drawn + c.culledOffscreen + c.culledHuge + c.culledDegenerate + c.culledOccluded;
    std::printf("  footprints computed %llu, %.2f per splat drawn\n", ull(computed),
                c.drawn ? double(computed) / double(c.drawn) : 0.0);
    std::printf("  drawn %llu (reconstruction %llu, low-pass %llu, ewa %llu); culled transparent %llu, near %llu "
                "(near layer %llu, dropped %llu), offscreen %llu, huge %llu, degenerate %llu, hidden behind "
                "opaque %llu\n", ull(c.drawn), ull(c.drawnPerMode[0]), ull(c.drawnPerMode[1]), ull(c.drawnPerMode[2]),
                ull(c.culledTransparent), ull(c.culledNear), ull(c.nearLayer), ull(c.droppedNear),
                ull(c.culledOffscreen), ull(c.culledHuge), ull(c.culledDegenerate), ull(c.culledOccluded));
}

// What a guard left out of the image, on stderr: kernels at the near plane beyond what the near layer takes
// (near_layer.h), all of them where a frame has no near layer, and, where SplatSettings::maxFootprintFraction
// is set, huge footprints. Counted when the counters ran; otherwise found on the CPU (findNearKernels) or,
// without a near layer, the near plane is checked against the volume's nearest voxel.
void reportDroppedSplats(const Scene& s, const SplatCounters* counted) {
    const bool layer = hasNearLayer(s.plane, s.settings);
    const uint64_t dropped = counted ? counted->droppedNear
                                     : layer ? findNearKernels(s.scene, s.plane, s.settings).dropped : 0;
    if (dropped > 0)
        std::fprintf(stderr, "note: %llu kernels at the near plane (%g from the eye) were left out: the near "
                             "layer takes at most %d\n", (unsigned long long)dropped, s.plane.nearDepth, kMaxNearKernels);
    if (counted) {
        if (!layer && counted->culledNear > 0)
            std::fprintf(stderr, "note: %llu splats whose kernels reach the near plane (%g from the eye) were not "
                                 "drawn; the ground truth clips their kernels there\n",
                         (unsigned long long)counted->culledNear, s.plane.nearDepth);
        if (counted->culledHuge > 0)
            std::fprintf(stderr, "note: %llu footprints wider than %g image diagonals were not drawn\n",
                         (unsigned long long)counted->culledHuge, s.settings.maxFootprintFraction);
        return;
    }
    const glm::dvec2 depths = s.plane.depthRange(s.scene.dims, s.scene.origin, s.scene.spacing);
    if (!layer && !s.plane.orthographic && depths.x <= s.plane.nearDepth)
        std::fprintf(stderr, "note: the near plane (%g from the eye) cuts the volume: voxels nearer are not drawn "
                             "(the ground truth clips their kernels there); --counters counts them\n",
                     s.plane.nearDepth);
}

// Milliseconds with three significant digits or more: 98.1, 5.02, 0.213.
std::string formatMs(double ms) {
    char text[32];
    std::snprintf(text, sizeof text, ms >= 100.0 ? "%.0f" : ms >= 10.0 ? "%.1f" : ms >= 1.0 ? "%.2f" : "%.3f", ms);
    return text;
}

// How the frames composite: the setting, or the image-aligned slabs that replace it.
std::string compositingText(const Scene& s, const RenderArgs& ra) {
    return ra.slabs.thickness > 0.0 ? slabsText(ra.slabs) : compositingName(s.settings.compositing);
}

// render --orbit: the turn drawn with GL or on the CPU (the oracle, or its image-aligned slabs), its
// summary printed, the frame after the largest jump to --out.
int runOrbit(const Scene& s, const SceneArgs& a, const RenderArgs& ra) {
    OrbitSummary orbit;
    std::string device = "CPU oracle (double)";
    if (ra.slabs.thickness > 0.0) {
        const SlabFrames slabs(ra.cpu);
        orbit = measureOrbit([&](const ImagePlane& p) { return slabs.render(s.scene, p, s.settings, ra.slabs); },
                             s.scene, s.camera, s.plane.width, s.plane.height, ra.orbitStep);
        device = slabs.device();
    } else if (ra.cpu) {
        orbit = measureOrbit([&](const ImagePlane& p) { return renderReference(s.scene, p, s.settings); }, s.scene,
                             s.camera, s.plane.width, s.plane.height, ra.orbitStep);
    } else {
        auto context = HeadlessGl::create();
        SplatRenderer gl;
        gl.setScene(s.scene);
        orbit = measureOrbit([&](const ImagePlane& p) { gl.render(p, s.settings); return gl.readback(); }, s.scene,
                             s.camera, s.plane.width, s.plane.height, ra.orbitStep);
        device = glRendererName();
    }
    if (!ra.orbitCsv.empty()) writeFileAtomically(ra.orbitCsv, orbitCsv(orbit));
    writeImage(orbit.worstFrame, a.out, s.background.data());
    std::printf("%s: %s, %s, %s on %s\n", a.out.c_str(), orbitSummaryText(orbit, ra.orbitStep).c_str(),
                filterModeName(s.settings.filter), compositingText(s, ra).c_str(), device.c_str());
    return 0;
}

int runRender(const SceneArgs& a, RenderArgs ra) {
    const int frames = ra.frames;
    if ((ra.slabs.postClassified || ra.slabs.supersample != 0) && ra.slabs.thickness == 0.0)
        throw CLI::ValidationError(ra.slabs.postClassified ? "--post-classify" : "--supersample",
                                   "applies to image-aligned slabs: give --image-slabs THICKNESS");
    if (ra.slabs.thickness != 0.0) {
        if (!(ra.slabs.thickness >= kMinSlabThickness && ra.slabs.thickness <= kMaxSlabThickness))
            throw CLI::ValidationError("--image-slabs", "expected a slab thickness of 0.05 to 64 voxels");
        if (!ra.heatmap.empty()) throw CLI::ValidationError("--heatmap", "the image-aligned slabs draw no heatmap");
    }
    const bool cpu = ra.cpu;
    if (frames < 1) throw CLI::ValidationError("--frames", "must be >= 1");
    checkImageWritable(a.out);   // before the volume loads and the frames render
    const bool orbit = !std::isnan(ra.orbitStep) || !ra.orbitCsv.empty();
    if (orbit) {
        checkOrbitStep(ra.orbitStep);
        if (!ra.heatmap.empty() || ra.counters)
            throw CLI::ValidationError("--orbit", "compares whole frames: not with --heatmap or --counters");
        if (!ra.orbitCsv.empty()) checkFileReplaceable(ra.orbitCsv);
    }
    if (ra.detailLevels < 0 || ra.detailLevels > 3) throw CLI::ValidationError("--detail-levels", "must be 0 to 3 halvings");
    Scene s = buildScene(a, ra.splat, ra.detailLevels);
    if (orbit) return runOrbit(s, a, ra);
    s.settings.heatmap = !ra.heatmap.empty();
    if (s.settings.heatmap && std::filesystem::path(ra.heatmap).lexically_normal() ==
                                  std::filesystem::path(a.out).lexically_normal())
        throw CLI::ValidationError("--heatmap", "'" + ra.heatmap + "' is also --out: the heatmap would replace the image");
    if (s.settings.heatmap) checkImageWritable(ra.heatmap);
    s.settings.counters = ra.counters;
    Image heatmap;
    Image image;
    std::vector<double> ms;
    std::string device;
    SplatCounters counters;
    SlabCounters slabs;
    if (ra.slabs.thickness > 0.0) {   // timed as the GL frames are: the first one (programs, set-up) untimed
        const SlabFrames renderer(cpu);
        device = renderer.device();
        for (int i = cpu ? 0 : -1; i < frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            image = renderer.render(s.scene, s.plane, s.settings, ra.slabs, &slabs);
            if (i >= 0) ms.push_back(msSince(t0));
        }
        counters = slabs.splats;
    } else if (cpu) {
        device = "CPU oracle (double)";
        for (int i = 0; i < frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            image = renderReference(s.scene, s.plane, s.settings, &counters, s.settings.heatmap ? &heatmap : nullptr);
            ms.push_back(msSince(t0));
        }
    } else {
        auto context = HeadlessGl::create();
        device = glRendererName();
        if (a.session.empty() && cullingByDriver(ra.splat))
            s.settings.occlusionCulling = driverProfile(device).occlusionCulling;
        SplatRenderer gl;
        gl.setScene(s.scene);
        gl.render(s.plane, s.settings);   // warm-up: shader compilation and first-use costs
        glFinish();
        for (int i = 0; i < frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            gl.render(s.plane, s.settings);
            glFinish();
            ms.push_back(msSince(t0));
        }
        gl.collectTimers();   // the last frame's, finished by its glFinish
        std::string passes;
        for (int i = 0; i < kGpuPasses; ++i)
            if (const double passMs = gl.stats().passMs[size_t(i)]; passMs > 0.0)
                passes += (passes.empty() ? "" : ", ") + std::string(gpuPassName(GpuPass(i))) + " " + formatMs(passMs);
        std::printf("  GPU %s ms in the last frame: %s\n", formatMs(gl.stats().gpuMs).c_str(),
                    passes.empty() ? "no pass ran" : passes.c_str());
        const int readBacks = gl.stats().readBacks;
        image = gl.readback();
        std::printf("  %d buffer read-back%s inside the last frame%s\n", readBacks, readBacks == 1 ? "" : "s",
                    gl.stats().redone ? "; its lists, sized from the frames before, were too short: drawn again" : "");
        if (s.settings.heatmap) heatmap = gl.readbackHeatmap();
        if (ra.counters) {   // one more frame with the GPU's counters on (they wait for the frame)
            SplatSettings counted = s.settings;
            counted.counters = true;
            gl.render(s.plane, counted);
            counters = gl.stats().counters;
            if (gl.stats().tiles)
                std::printf("  %llu splat-tile pairs composited\n", (unsigned long long)gl.stats().tileEntries);
            else
                std::printf("  %llu fragments passed (all passes)\n", (unsigned long long)gl.stats().fragments);
        }
        std::printf("  %s, %.2f GPU bytes per voxel (the scene), %.1f MiB more for the frame's passes\n",
                    primitiveName(gl.stats()).c_str(), double(gl.sceneBytes()) / double(s.scene.classes.size()),
                    double(gl.workingBytes()) / (1024.0 * 1024.0));
        if (const std::string splits = tileSplitsText(gl.stats()); !splits.empty()) std::printf("  %s\n", splits.c_str());
    }
    writeImage(image, a.out, s.background.data());
    if (s.settings.heatmap) writeImage(heatmap, ra.heatmap, s.background.data());
    std::sort(ms.begin(), ms.end());
    std::printf("%s: %dx%d, %zu splats, %s, %s, %.2f ms/frame (median of %d) on %s\n", a.out.c_str(),
                s.plane.width, s.plane.height, s.scene.visibleCount(), filterModeName(s.settings.filter),
                compositingText(s, ra).c_str(), ms[ms.size() / 2], frames, device.c_str());
    if (ra.counters) printCounters(counters);
    if (ra.slabs.thickness > 0.0 && ra.counters)
        std::printf("  %llu slabs; %llu footprint pixels written %llu times into them (%.2f slabs each)\n",
                    (unsigned long long)slabs.slabs, (unsigned long long)slabs.footprintPixels,
                    (unsigned long long)slabs.slabWrites,
                    slabs.footprintPixels ? double(slabs.slabWrites) / double(slabs.footprintPixels) : 0.0);
    reportDroppedSplats(s, ra.counters || ra.cpu ? &counters : nullptr);
    return 0;
}


int runReference(const SceneArgs& a, const SplatFlags& splat, const GroundTruthOptions& options,
                 const std::string& cacheDir, bool noCache) {
    checkImageWritable(a.out);   // before the rays are traced
    SplatFlags compositingOnly;   // of the splatting flags, the ground truth depends on compositing only
    compositingOnly.compositing = splat.compositing;
    const Scene s = buildScene(a, compositingOnly);
    GroundTruthStats stats;
    const Image image = noCache ? renderGroundTruth(s.scene, s.plane, s.settings, options, printProgress, &stats)
                                : cachedGroundTruth(s.scene, s.plane, s.settings, options,
                                                    cacheDir.empty() ? defaultGroundTruthCacheDir() : std::filesystem::path(cacheDir),
                                                    printProgress, &stats);
    writeImage(image, a.out);
    if (stats.fromCache)
        std::printf("%s: reference from the cache (key %s)\n", a.out.c_str(),
                    groundTruthKey(s.scene, s.plane, s.settings, options).c_str());
    else
        std::printf("%s: reference of %llu rays in %.1f s, %.2f step halvings per ray, %llu rays not converged "
                    "to %.1e\n",
                    a.out.c_str(), (unsigned long long)stats.rays, stats.seconds, stats.meanHalvings,
                    (unsigned long long)stats.unconvergedRays, options.tolerance);
    if (!stats.cacheNote.empty()) std::fprintf(stderr, "splatlab: note: not cached: %s\n", stats.cacheNote.c_str());
    return 0;
}

// `splatlab tf`: the built-in presets' names, or one TF (a preset or a JSON file) as the JSON file the
// editor loads, so a preset can be the start of a user's own.
int runTf(const std::string& spec, const std::string& out, bool paraView) {
    if (spec.empty()) {
        for (const std::string& name : builtinPresetNames()) std::printf("%s\n", name.c_str());
        return 0;
    }
    const TransferFunction tf = tfFromSpecNoting(spec);
    if (paraView && !tf.gradientOpacity.empty())   // said, not dropped silently
        std::fprintf(stderr,
                     "splatlab: note: ParaView's colour-map presets hold no gradient opacity: the TF's %zu gradient "
                     "opacity points are not written (SplatLab's JSON keeps them)\n",
                     tf.gradientOpacity.size());
    if (paraView && !tf.widgets2d.empty())
        std::fprintf(stderr,
                     "splatlab: note: ParaView's colour-map presets hold no 2D transfer function: the TF's %zu 2D "
                     "widgets are not written (SplatLab's JSON keeps them)\n",
                     tf.widgets2d.size());
    if (paraView && out.empty()) std::fputs(paraViewPresetText(tf).c_str(), stdout);
    else if (paraView) saveParaViewPreset(tf, out);
    else if (out.empty()) std::fputs(transferFunctionText(tf).c_str(), stdout);
    else saveTransferFunction(tf, out);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"SplatLab: adaptive EWA volume splatting"};
    app.require_subcommand(0, 1);

    SceneArgs r;
    RenderArgs ra;
    auto* render = app.add_subcommand("render", "Render a volume headless to an image (PNG, EXR, ...)");
    addSceneOptions(render, r);
    addSplatFlags(render, ra.splat);
    render->add_option("--heatmap", ra.heatmap, "Also write the filter-mode heatmap (red reconstruction, green "
                                                "low-pass, blue EWA, weighted by opacity)");
    render->add_flag("--counters", ra.counters, "Print splats per filter and per cull (GL: counted on the GPU)");
    render->add_option("--frames", ra.frames, "Timed frames (the median is printed)")->capture_default_str();
    render->add_option("--detail-levels", ra.detailLevels, "Far views: draw the volume halved up to this many times "
                       "where the level's kernels stay under the low-pass threshold and keep the optical mass "
                       "(0: full resolution)")->capture_default_str();
    render->add_flag("--cpu", ra.cpu, "Render with the double-precision CPU oracle instead of GL");
    render->add_option("--image-slabs", ra.slabs.thickness, "Composite slabs parallel to the image, this many voxels thick, "
                       "instead of the volume's slices (front to back; kernels prepared on the CPU, pixels on the GPU or "
                       "with --cpu on the CPU oracle)");
    render->add_flag("--post-classify", ra.slabs.postClassified, "With --image-slabs: apply the TF to each slab's "
                     "reconstructed value instead of to each voxel (1D TFs)");
    render->add_option("--supersample", ra.slabs.supersample, "With --image-slabs: S x S samples a pixel, resolved by "
                       "the ground truth's 1-px Gaussian (0..4; 0: one sample, no resolve)");
    render->add_option("--orbit", ra.orbitStep, "Turn the camera about the up axis in steps of this many degrees and "
                                                "print how much each frame differs from the one before (popping); "
                                                "--out gets the frame after the largest jump");
    render->add_option("--orbit-csv", ra.orbitCsv, "With --orbit: each frame's azimuth, slice axis and RMSE");
    render->add_option("--session", r.session,
                       "Render a session saved by the editor: its volume, TF, window, camera, settings and background "
                       "(a volume argument replaces its volume; --size, --out, --heatmap, --counters, --frames and "
                       "--cpu still apply)");
    render->get_option("volume")->required(false);

    SceneArgs ref;
    GroundTruthOptions gt;
    std::string cacheDir;
    bool noCache = false;
    auto* reference = app.add_subcommand("reference", "Compute (or reuse) the ground-truth image of a view");
    addSceneOptions(reference, ref);
    reference->add_option("--tolerance", gt.tolerance, "Per-ray convergence: max RGBA change when the step halves")
        ->capture_default_str();
    reference->add_option("--supersample", gt.supersample, "Rays per pixel axis for the 1-px low-pass (1..8)")
        ->capture_default_str()
        ->check(CLI::Range(1, 8));
    // The ground truth depends on how the volume looks and, of the splatting flags, on compositing only:
    // X-ray's truth is the integral without attenuation, every other mode's the absorption-emission one.
    SplatFlags refSplat;
    const size_t beforeCompositing = reference->get_options().size();
    reference->add_option("--compositing", refSplat.compositing,
                          "Whose truth: xray (the integral without attenuation) or any other mode (absorption and "
                          "emission; splat-every-sample, sheet-back-to-front and sheet-front-to-back share it)")
        ->capture_default_str();
    sessionSets(reference, beforeCompositing);
    reference->add_option("--session", ref.session,
                          "The ground truth of a session saved by the editor: its volume, TF, window, camera and "
                          "compositing (a volume argument replaces its volume; --size and --out still apply)");
    reference->get_option("volume")->required(false);
    reference->add_flag("--post-classified", gt.postClassified, "The truth of post-classification: the TF applied to "
                        "the kernels' mean value along each ray (render --image-slabs T --post-classify)");
    reference->add_option("--cache", cacheDir, "Cache folder (default: ~/.cache/splatlab/reference)");
    reference->add_flag("--no-cache", noCache, "Always compute, never read or write the cache");

    CompareArgs cmp;
    auto* compare = addCompareCommand(app, cmp);

    std::string infoPath;
    RawFlags infoRaw;
    bool infoGradients = false;
    auto* info = app.add_subcommand("info", "Print dims, type, spacing, range and a histogram of a volume");
    info->add_option("volume", infoPath, "Volume file")->required();
    info->add_flag("--gradients", infoGradients,
                   "Also compute the gradients (progress bar on stderr) and print their stats");
    addRawFlags(info, infoRaw);

    std::string tfSpec, tfOut;
    bool tfParaView = false;
    auto* tfCommand = app.add_subcommand("tf", "List the built-in transfer functions, or print one as the JSON file "
                                               "the editor and --tf load");
    tfCommand->add_option(
        "name", tfSpec, "A preset name, a JSON file or a Slicer presets.xml[#NAME] (none: list the presets)");
    tfCommand->add_option("--out", tfOut, "Write it to this file instead of printing it");
    tfCommand->add_flag("--paraview", tfParaView,
                        "As a ParaView colour-map preset (JSON: RGBPoints, Points) its Color Map Editor imports");

    AccuracyArgs acc;
    auto* accuracy = addAccuracyCommand(app, acc);
    ReportArgs reportArgs;
    auto* report = addReportCommand(app, reportArgs);
    PhantomArgs phantomArgs;
    auto* phantom = addPhantomCommand(app, phantomArgs);

    EditorOptions e;
    e.volumePath = std::filesystem::path(SPLATLAB_ASSET_DIR) / "volumes" / "bonsai.nhdr";
    std::string editorSize = "1280x800", editorVolume, screenshot, editorUp, editorCamera, editorSession;
    LookFlags editorLook;
    SplatFlags editorSplat;
    RawFlags editorRaw;
    auto* editor = app.add_subcommand("editor", "Open the editor window (default: the bundled bonsai, 128^3, "
                                                 "framed, with --tf bonsai, lit per splat)");
    std::vector<std::string> sceneNames;
    for (const DemoSceneInfo& scene : demoSceneList()) sceneNames.push_back(scene.name);
    auto* editorVolumeOption = editor->add_option("volume", editorVolume, "Volume file (or scene:NAME, a demo scene)");
    editor
        ->add_option("--tf", e.tfSpec,
                     "Transfer function: a preset name, a JSON file or a 3D Slicer presets.xml "
                     "(FILE.xml#NAME picks one)")
        ->capture_default_str()
        ->group(kSessionSetGroup);
    auto* editorSessionOption = editor->add_option("--session", editorSession,
                       "Open a saved session (JSON): its volume, TF, window, camera and settings (a volume argument "
                       "replaces its volume)");
    editor->add_option("--scene", e.sceneName, "Open a demo scene (Settings > Files > Demo scene) in its TF and view")
        ->check(CLI::IsMember(sceneNames))->excludes(editorVolumeOption)->excludes(editorSessionOption);
    editor->add_option("--screenshot", screenshot, "Write a PNG of the window after --frames frames, then exit");
    editor->add_option("--frames", e.frames, "Exit after this many frames (0: run until closed)")
        ->check(CLI::NonNegativeNumber);
    editor->add_option("--size", editorSize, "Window size WxH")->capture_default_str();
    const size_t viewFlags = editor->get_options().size();
    editor->add_option("--camera", editorCamera, "Starting view: azimuth,elevation,distance,fov");
    editor->add_flag("--fit", e.fit, "Start framed: everything the TF shows fills the viewport, centred "
                                     "(Settings > Camera > Frame)");
    editor->add_flag("--heatmap", e.settings.heatmap, "Start with the filter-mode heatmap over the image in the viewport");
    editor->add_option("--heatmap-opacity", e.heatmapOpacity, "The heatmap over the image: 0 the image only, 1 the "
                                                              "heatmap only")->capture_default_str()->check(CLI::Range(0.0, 1.0));
    std::string editorSplit, editorSplitDifference;
    editor->add_option("--split", editorSplit, "Split the viewport in two or four panes at one camera with these "
                                               "filters, e.g. reconstruction,ewa (Settings > Split view)");
    editor->add_option("--split-difference", editorSplitDifference, "With --split: a difference pane, |A - B| (no "
                                                                    "value) or |A - ground truth| ('truth')")
        ->expected(0, 1);
    editor->add_option("--up", editorUp, "Axis of the file's world frame shown upwards: x, y, z, -x, -y, -z (default: z; "
                                         "y for the bundled bonsai)");
    sessionSets(editor, viewFlags);
    addLookFlags(editor, editorLook);
    addSplatFlags(editor, editorSplat);
    addRawFlags(editor, editorRaw);
    editor->add_option("--tab", e.tabs, "Bring a panel's tab to the front, e.g. Performance (repeatable)");
    editor->add_flag("--continuous", e.continuous, "Render every frame (the Performance panel's steady load)");
    editor->add_option("--save-image", e.saveImagePath,
                       "Save the view as Settings > Save image does (.png, or .exr for float RGBA), then exit");
    editor->add_flag("--preview", e.preview,
                     "Show the preview level alone: large volumes (" +
                         std::to_string(ui::PreviewSettings::kMinMegaVoxels) + " M voxels or more) at half resolution");
    editor->add_option("--session-out", e.sessionOutPath, "When the editor closes, save the session (what it shows) here");
    editor->add_option("--measure-interactive", e.measureEdits, "Turn the camera N times, print edit-to-image and UI "
                                                                "frame times (docs/speed.md), close")->check(CLI::PositiveNumber);
    editor->add_option("--spin", e.spinDegPerS, "Render continuously, turning the camera this many degrees a second");

    try {
        app.parse(argc, argv);
        if (*render && !r.session.empty()) rejectFlagsBesideSession(render);
        if (*reference && !ref.session.empty()) rejectFlagsBesideSession(reference);
        if (*editor && !editorSession.empty()) rejectFlagsBesideSession(editor);
        if (*render) return runRender(r, ra);
        if (*reference) return runReference(ref, refSplat, gt, cacheDir, noCache);
        if (*compare) return runCompare(cmp);
        if (*info) return runInfo(infoPath, rawOptions(infoRaw), infoGradients);
        if (*accuracy) return runAccuracy(acc);
        if (*report) return runReport(reportArgs);
        if (*tfCommand) return runTf(tfSpec, tfOut, tfParaView);
        if (*phantom) return runPhantom(phantomArgs);
        // No volume and no session: the bundled bonsai (assets/volumes/MANIFEST.md) as it looks best, each
        // default giving way to its flag. Its trunk grows along +y. It is framed from a three-quarter view
        // a little above the rim (unless --camera says where), in its preset, lit per splat (once the
        // gradients are in, a fraction of a second after it opens). Its voxels are twice as long as the
        // 256^3 scan's, so twice the density per voxel length keeps that scan's extinction per unit length.
        const bool bundled = editorVolume.empty() && editorSession.empty() && e.sceneName.empty();
        const auto unset = [&](const char* flag) { return editor->get_option(flag)->count() == 0; };
        if (bundled) {
            e.upAxis = "y";
            e.camera = parseCamera("30,20,2.5,30");
            if (unset("--camera")) e.fit = true;
            if (unset("--tf")) e.tfSpec = "bonsai";
            if (unset("--shading")) editorLook.shading = "per-splat";
            if (unset("--density")) editorLook.density = 2.0;
        }
        if (!editorCamera.empty()) e.camera = parseCamera(editorCamera);
        e.split = parseSplit(editorSplit);
        if (editor->get_option("--split-difference")->count() > 0)
            e.splitDifference = parseSplitDifference(editorSplitDifference, !e.split.empty());
        applyLookFlags(editorLook, e.settings);
        applySplatFlags(editorSplat, e.settings);
        e.cullingByDriver = cullingByDriver(editorSplat);
        e.camera.orthographic = editorLook.orthographic;
        e.window = parseWindow(editorLook.window);
        e.raw = rawOptions(editorRaw);
        if (!editorUp.empty()) e.upAxis = (axisFromName(editorUp), editorUp);
        if (!editorVolume.empty()) e.volumePath = editorVolume;
        else if (!editorSession.empty()) e.volumePath.clear();   // the session's volume
        else if (!e.sceneName.empty()) e.volumePath = demoScenePath(e.sceneName);
        e.sceneLook = unset("--tf") && unset("--density") && unset("--shading");
        e.sceneCamera = unset("--camera") && !e.fit;
        e.sessionPath = editorSession;
        if (!screenshot.empty()) e.screenshotPath = screenshot;
        const glm::ivec2 s = parseSize(editorSize, "--size");
        e.width = s.x;
        e.height = s.y;
        if ((!screenshot.empty() || !e.saveImagePath.empty()) && e.frames < 1) e.frames = 5;
        for (const std::filesystem::path& out : {e.saveImagePath, e.screenshotPath})   // before the window opens
            if (!out.empty()) checkImageWritable(out);
        return runEditor(e);
    } catch (const CLI::ParseError& err) {
        return app.exit(err);
    } catch (const std::bad_alloc&) {   // the steps name what they allocate; this is what none named
        std::fprintf(stderr, "splatlab: out of memory\n");
        return 1;
    } catch (const std::exception& err) {
        std::fprintf(stderr, "splatlab: %s\n", err.what());
        return 1;
    }
}
