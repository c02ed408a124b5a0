// The flags the commands share (how the volume looks and is splatted, a raw file's layout, the view),
// and the scene `render` and `reference` build from them or from a saved editor session.
#pragma once
#include "renderer/io/volume_io.h"
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/window.h"
#include "renderer/oracle/image_slabs.h"

#include <CLI/CLI.hpp>

#include <array>
#include <optional>
#include <string>

// The help group of every flag for something a saved session also sets (the camera, the TF, how the
// volume looks and is splatted): beside `--session` each is refused, found by this group.
extern const char* const kSessionSetGroup;
// Puts the options `cmd` gained since it had `before` of them in kSessionSetGroup.
void sessionSets(CLI::App* cmd, size_t before);
// `render --session`, `editor --session`: a flag for what the session sets is an error beside it, not
// silently overridden by the session or overriding it.
void rejectFlagsBesideSession(const CLI::App* cmd);

// A headerless raw file's layout.
struct RawFlags {
    std::string dims, type, endian = "little";
};
std::optional<renderer::RawOptions> rawOptions(const RawFlags& f);
void addRawFlags(CLI::App* cmd, RawFlags& raw);

// "data", "p1-99" or "LO,HI" in data units.
renderer::WindowSettings parseWindow(const std::string& text);

// How the volume looks: the flags `render`, `reference` and the editor share.
struct LookFlags {
    std::string window = "data", shading = "none";
    double kernelScale = renderer::SplatSettings{}.kernelScale, cutoff = renderer::SplatSettings{}.cutoffSigmas, density = 1.0;
    double surfaceFlatten = 1.0, surfaceGradient = renderer::SplatSettings{}.surfaceGradient;
    bool orthographic = false;
};
void addLookFlags(CLI::App* cmd, LookFlags& f);
void applyLookFlags(const LookFlags& f, renderer::SplatSettings& s);

// How splats are filtered, composited and culled: the flags `render` and the editor share.
struct SplatFlags {
    // Both start with tiled sheets front to back: the fastest mode on every machine measured, and as close
    // to the ground truth as splat-every-sample.
    std::string compositing = "sheet-front-to-back", filter = "ewa", primitive = "auto";
    double cMin = renderer::SplatSettings{}.cMin, cMax = renderer::SplatSettings{}.cMax, hysteresis = renderer::SplatSettings{}.hysteresis;
    double opaqueAlpha = renderer::SplatSettings{}.opaqueAlpha;
    int patchSize = renderer::SplatSettings{}.patchSize, opaqueRefresh = renderer::SplatSettings{}.opaqueRefreshSlices;
    bool noOcclusionCulling = false, occlusionCulling = false;   // neither: the driver's default
};
void addSplatFlags(CLI::App* cmd, SplatFlags& f);
void applySplatFlags(const SplatFlags& f, renderer::SplatSettings& s);
// Neither culling flag: the driver's profile chooses, once the GL context exists.
bool cullingByDriver(const SplatFlags& f);

// What `render` and `reference` share: the volume, the view and how it looks.
struct SceneArgs {
    std::string volume, out, size = "512x512", camera = "30,20,2.5,30", tf = "ct-skin-bone", up = "z";
    std::string session;   // render --session: a saved editor session instead of the flags above
    bool fit = false;
    LookFlags look;
    RawFlags raw;
};
void addSceneOptions(CLI::App* cmd, SceneArgs& a);

// A volume classified and seen as the flags or the session say.
struct Scene {
    renderer::SplatScene scene;
    renderer::Camera camera;   // the plane's (framed when --fit)
    renderer::ImagePlane plane;
    renderer::SplatSettings settings;
    std::array<float, 3> background{0.0f, 0.0f, 0.0f};   // behind a PNG: black, or the session's
    // A session's image-aligned slabs, where the editor ends its still view in them (slabsOfStillView).
    std::optional<renderer::SlabOptions> slabs;
};

// The scene of the flags, or of `a.session` (a volume argument replacing its volume). detailLevels > 0:
// a far view from a coarser level, at most that many halvings (render --detail-levels).
Scene buildScene(const SceneArgs& a, const SplatFlags& splat, int detailLevels = 0);
// The TF a --tf spec names; what an import leaves out (a Slicer preset's gradient opacity) goes to stderr.
renderer::TransferFunction tfFromSpecNoting(const std::string& spec);
