// The flags the commands share and the scene built from them or from a session (scene_flags.h).
#include "scene_flags.h"

#include "cli_parse.h"
#include "console_progress.h"
#include "far_view_level.h"
#include "slab_frames.h"

#include "renderer/errors.h"
#include "renderer/model/gradients.h"
#include "renderer/oracle/demo_scenes.h"
#include "ui/session.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

using namespace renderer;

const char* const kSessionSetGroup = "What a session sets";

namespace {

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

// A flag's number, checked against the range a session accepts for its setting (splat_settings.h).
double inRange(double value, const char* flag, SettingRange range, const char* unit = "") {
    if (!range.holds(value)) throw CLI::ValidationError(flag, "must be " + formatRange(range.lo, range.hi) + unit);
    return value;
}

const char* kPrimitiveHelp = "How splats reach pixels: auto (tiles for sheets and X-ray, else raster), raster "
                             "(per slice: points where they fit, else quads), points, quads, or tiles (compute passes; sheets "
                             "and X-ray only)";

// The volume classified by `tf` over `window`, its gradients when the settings or the TF need them, and
// the view.
// detailLevels > 0: a far view from a coarser level, at most that many halvings (render --detail-levels).
void finishScene(Scene& s, const std::filesystem::path& volumePath, const RawFlags& raw, const TransferFunction& tf,
                 const WindowSettings& window, Camera camera, glm::ivec2 size, bool fit, int detailLevels) {
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
    s.slabs = slabsOfStillView(state.slabs, state.settings);
    finishScene(s, volume, a.raw, state.tf, state.window, state.camera, parseSize(a.size, "--size"), false, detailLevels);
    return s;
}

} // namespace

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

// Puts the options `cmd` gained since it had `before` of them in kSessionSetGroup.
void sessionSets(CLI::App* cmd, size_t before) {
    const std::vector<CLI::Option*> options = cmd->get_options(std::function<bool(CLI::Option*)>{});
    for (size_t i = before; i < options.size(); ++i) options[i]->group(kSessionSetGroup);
}

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

void rejectFlagsBesideSession(const CLI::App* cmd) {
    for (const CLI::Option* o : cmd->get_options())
        if (o->get_group() == kSessionSetGroup && o->count() > 0)
            throw CLI::ValidationError(o->get_name(), "not with --session: the session sets it");
}

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

TransferFunction tfFromSpecNoting(const std::string& spec) {
    std::vector<std::string> notes;
    TransferFunction tf = transferFunctionFromSpec(spec, &notes);
    for (const std::string& note : notes)
        std::fprintf(stderr, "splatlab: note: %s\n", note.c_str());
    return tf;
}

Scene buildScene(const SceneArgs& a, const SplatFlags& splat, int detailLevels) {
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
