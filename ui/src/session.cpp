// Sessions as JSON (session.h). Loading reads into a copy of the state, section by section, and
// checks every value it finds; the copy replaces the state only once the whole file passed.
#include "ui/session.h"

#include "renderer/io/atomic_file.h"
#include "renderer/errors.h"
#include "renderer/io/json_file.h"
#include "renderer/model/splat_settings.h"
#include "renderer/oracle/demo_scenes.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace ui {

namespace {

using nlohmann::json;

// One section of a session file being read: each accessor leaves its output alone when the key is
// absent and throws LoadError ("section.key", what was expected) when it holds something else.
class Section {
  public:
    Section(const json& root, const char* name, const std::string& file) : m_file(file), m_name(name) {
        if (!root.contains(name)) return;
        if (!root[name].is_object()) fail("", "expected an object");
        m_json = &root[name];
    }

    void number(const char* key, double& out, renderer::SettingRange range) const { number(key, out, range.lo, range.hi); }
    void integer(const char* key, int& out, renderer::SettingRange range) const {
        integer(key, out, int(range.lo), int(range.hi));
    }
    void number(const char* key, double& out, double lo, double hi) const {
        if (const json* v = find(key)) {
            if (!v->is_number() || !std::isfinite(v->get<double>()) || v->get<double>() < lo || v->get<double>() > hi)
                fail(key, "expected a number in [" + text(lo) + ", " + text(hi) + "]");
            out = v->get<double>();
        }
    }
    void integer(const char* key, int& out, int lo, int hi) const {
        if (const json* v = find(key)) {
            if (!v->is_number_integer() || v->get<long long>() < lo || v->get<long long>() > hi)
                fail(key, "expected a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
            out = v->get<int>();
        }
    }
    void boolean(const char* key, bool& out) const {
        if (const json* v = find(key)) {
            if (!v->is_boolean()) fail(key, "expected true or false");
            out = v->get<bool>();
        }
    }
    // An enum by the renderer's name for it (its FromName lists the names it knows).
    template <class E>
    void name(const char* key, E& out, E (*fromName)(const std::string&)) const {
        if (const json* v = find(key)) {
            if (!v->is_string()) fail(key, "expected a name (a string)");
            try {
                out = fromName(v->get<std::string>());
            } catch (const renderer::RenderError& e) {
                fail(key, e.what());
            }
        }
    }
    template <int N>
    void numbers(const char* key, double (&out)[N], double lo, double hi) const {
        if (const json* v = find(key)) {
            const std::string expected =
                "expected " + std::to_string(N) + " numbers in [" + text(lo) + ", " + text(hi) + "]";
            if (!v->is_array() || v->size() != size_t(N)) fail(key, expected);
            for (int i = 0; i < N; ++i) {
                const json& x = (*v)[size_t(i)];
                if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < lo || x.get<double>() > hi)
                    fail(key, expected);
                out[i] = x.get<double>();
            }
        }
    }
    const json* find(const char* key) const { return m_json && m_json->contains(key) ? &(*m_json)[key] : nullptr; }
    [[noreturn]] void fail(const char* key, const std::string& expected) const {
        throw renderer::LoadError(m_file, *key ? m_name + "." + key : m_name, expected);
    }

  private:
    static std::string text(double x) {
        char s[32];
        std::snprintf(s, sizeof s, "%g", x);
        return s;
    }
    std::string m_file, m_name;
    const json* m_json = nullptr;
};

} // namespace

void saveSession(const EditorState& state, const std::filesystem::path& volume, const std::filesystem::path& file) {
    json j;
    j["splatlab_session"] = kSessionVersion;
    if (const std::optional<std::string> scene = renderer::demoSceneOfPath(volume)) {
        j["scene"] = *scene;
    } else if (!volume.empty()) {
        // Relative to the session's folder where the two share a root; else as it is.
        const auto base = std::filesystem::absolute(file).parent_path();
        const auto relative = std::filesystem::absolute(volume).lexically_relative(base);
        j["volume"] = (relative.empty() ? volume : relative).generic_string();
    }
    j["transfer_function"] = renderer::toJson(state.tf);
    j["window"] = {{"mode", renderer::windowModeName(state.window.mode)},
                   {"lo", state.window.custom.lo},
                   {"hi", state.window.custom.hi}};
    const renderer::Camera& c = state.camera;
    j["camera"] = {{"azimuth", c.azimuthDeg}, {"elevation", c.elevationDeg}, {"distance", c.distance},
                   {"fov", c.fovYDeg},        {"pan", {c.panPx.x, c.panPx.y}}, {"up", {c.up.x, c.up.y, c.up.z}},
                   {"orthographic", c.orthographic}};
    const renderer::SplatSettings& s = state.settings;
    j["splatting"] = {{"kernel_scale", s.kernelScale},
                      {"cutoff", s.cutoffSigmas},
                      {"density", s.density},
                      {"filter", renderer::filterModeName(s.filter)},
                      {"c_min", s.cMin},
                      {"c_max", s.cMax},
                      {"patch_size", s.patchSize},
                      {"hysteresis", s.hysteresis},
                      {"compositing", renderer::compositingName(s.compositing)},
                      {"primitive", renderer::primitiveName(s.primitive)},
                      {"opaque_alpha", s.opaqueAlpha},
                      {"opaque_refresh_slices", s.opaqueRefreshSlices},
                      {"occlusion_culling", s.occlusionCulling},
                      {"shading", renderer::shadingName(s.shading)},
                      {"ambient", s.shadingParams.ambient},
                      {"diffuse", s.shadingParams.diffuse},
                      {"specular", s.shadingParams.specular},
                      {"shininess", s.shadingParams.shininess},
                      {"surface_flatten", s.surfaceFlatten},
                      {"surface_gradient", s.surfaceGradient},
                      {"counters", s.counters}};
    j["view"] = {{"heatmap", state.showHeatmap},
                 {"heatmap_opacity", state.heatmapOpacity},
                 {"histogram_log", state.histogramLog},
                 {"background", {state.background[0], state.background[1], state.background[2]}}};
    const SplitView& split = state.split;
    j["split"] = {{"enabled", split.enabled}, {"panes", split.imagePanes},
                  {"difference", splitDifferenceName(split.difference)}};
    for (size_t i = 0; i < split.panes.size(); ++i) { // all four: a 2-pane view keeps C and D for later
        const std::string pane(1, char('a' + i));
        j["split"]["filter_" + pane] = renderer::filterModeName(split.panes[i].filter);
        j["split"]["compositing_" + pane] = renderer::compositingName(split.panes[i].compositing);
    }
    j["slabs"] = {{"enabled", state.slabs.enabled},
                  {"thickness", state.slabs.thickness},
                  {"post_classified", state.slabs.postClassified}};
    j["space_mouse"] = {{"enabled", state.spaceMouse.enabled},
                        {"speed", state.spaceMouse.speed},
                        {"invert_rotation", state.spaceMouse.invertRotation},
                        {"invert_moves", state.spaceMouse.invertTranslation}};
    renderer::writeFileAtomically(file, j.dump(2) + "\n");
}

std::filesystem::path loadSession(const std::filesystem::path& file, EditorState& state) {
    const std::string name = file.string();
    json j = renderer::readJsonFile(file, "a SplatLab session (.json)");
    if (!j.is_object()) throw renderer::LoadError(name, "", "expected a JSON object");
    if (!j.contains("splatlab_session") || !j["splatlab_session"].is_number())
        throw renderer::LoadError(name, "splatlab_session", "missing: not a SplatLab session");
    // Versions are whole numbers from 1; nlohmann keeps 2^64-1 as unsigned and -5 as signed, so each
    // kind is checked as itself (a cast would turn one into the other).
    const json& version = j["splatlab_session"];
    if (!version.is_number_unsigned() || version.get<uint64_t>() < 1)
        throw renderer::LoadError(name, "splatlab_session",
                                  "version " + version.dump() + ": expected a whole number from 1 to " +
                                      std::to_string(kSessionVersion));
    if (version.get<uint64_t>() > uint64_t(kSessionVersion))
        throw renderer::LoadError(name, "splatlab_session",
                                  "version " + version.dump() + " is newer than this SplatLab reads (" +
                                      std::to_string(kSessionVersion) + ")");

    EditorState next = state;
    std::filesystem::path volume;
    if (j.contains("volume")) {
        if (!j["volume"].is_string() || j["volume"].get<std::string>().empty())
            throw renderer::LoadError(name, "volume", "expected the volume's path (a string)");
        volume = j["volume"].get<std::string>();
        if (volume.is_relative()) volume = (std::filesystem::absolute(file).parent_path() / volume).lexically_normal();
    }
    if (j.contains("scene")) { // a demo scene instead of a volume file
        if (!j["scene"].is_string() || !renderer::isDemoScene(j["scene"].get<std::string>()))
            throw renderer::LoadError(name, "scene", "one of the demo scenes: " + renderer::demoSceneNames());
        if (volume.empty()) volume = renderer::demoScenePath(j["scene"].get<std::string>());
    }
    if (j.contains("transfer_function")) {
        next.tf = renderer::transferFunctionFromJson(j["transfer_function"], name + " (transfer_function)",
                                                     next.tf.name);
        next.tfSelected = next.tfColourSelected = -1;
        next.tfEdited = false;
    }

    const Section window(j, "window", name);
    window.name("mode", next.window.mode, &renderer::windowModeFromName);
    double lo = next.window.custom.lo, hi = next.window.custom.hi;
    window.number("lo", lo, -3.4e38, 3.4e38);
    window.number("hi", hi, -3.4e38, 3.4e38);
    if (next.window.mode == renderer::WindowMode::Custom && !(lo < hi)) window.fail("hi", "expected hi > lo");
    next.window.custom = {float(lo), float(hi)};

    const Section camera(j, "camera", name);
    renderer::Camera& c = next.camera;
    camera.number("azimuth", c.azimuthDeg, -360.0, 360.0);
    camera.number("elevation", c.elevationDeg, -90.0, 90.0);
    camera.number("distance", c.distance, renderer::kMinCameraDistance, renderer::kMaxCameraDistance);
    camera.number("fov", c.fovYDeg, 1.0, 170.0);
    double pan[2] = {c.panPx.x, c.panPx.y}, up[3] = {c.up.x, c.up.y, c.up.z};
    camera.numbers("pan", pan, -1e6, 1e6);
    camera.numbers("up", up, -1.0, 1.0);
    c.panPx = {pan[0], pan[1]};
    const glm::dvec3 upVector(up[0], up[1], up[2]);
    if (!(glm::length(upVector) > 1e-6)) camera.fail("up", "expected a direction (not all zero)");
    c.up = glm::normalize(upVector);
    camera.boolean("orthographic", c.orthographic);

    const Section splatting(j, "splatting", name);
    renderer::SplatSettings& s = next.settings;
    splatting.number("kernel_scale", s.kernelScale, renderer::kKernelScaleRange);
    splatting.number("cutoff", s.cutoffSigmas, renderer::kCutoffRange);
    splatting.number("density", s.density, renderer::kDensityRange);
    splatting.name("filter", s.filter, &renderer::filterModeFromName);
    splatting.number("c_min", s.cMin, renderer::kCMinRange);
    splatting.number("c_max", s.cMax, renderer::kCMaxRange);
    splatting.integer("patch_size", s.patchSize, renderer::kPatchSizeRange);
    splatting.number("hysteresis", s.hysteresis, renderer::kHysteresisRange);
    splatting.name("compositing", s.compositing, &renderer::compositingFromName);
    splatting.name("primitive", s.primitive, &renderer::primitiveFromName);
    if (s.compositing == renderer::Compositing::SplatEverySample && s.primitive == renderer::SplatSettings::Primitive::Tiles)
        splatting.fail("primitive", "tiles need sheet or X-ray compositing");
    splatting.number("opaque_alpha", s.opaqueAlpha, renderer::kOpaqueAlphaRange);
    splatting.integer("opaque_refresh_slices", s.opaqueRefreshSlices, renderer::kOpaqueRefreshRange);
    splatting.boolean("occlusion_culling", s.occlusionCulling);
    splatting.name("shading", s.shading, &renderer::shadingFromName);
    splatting.number("ambient", s.shadingParams.ambient, 0.0, 10.0);
    splatting.number("diffuse", s.shadingParams.diffuse, 0.0, 10.0);
    splatting.number("specular", s.shadingParams.specular, 0.0, 10.0);
    splatting.number("shininess", s.shadingParams.shininess, 0.0, 1e4);
    splatting.number("surface_flatten", s.surfaceFlatten, renderer::kSurfaceFlattenRange);
    splatting.number("surface_gradient", s.surfaceGradient, renderer::kSurfaceGradientRange);
    splatting.boolean("counters", s.counters);

    const Section view(j, "view", name);
    view.boolean("heatmap", next.showHeatmap);
    s.heatmap = next.showHeatmap;
    view.number("heatmap_opacity", next.heatmapOpacity, 0.0, 1.0);
    view.boolean("histogram_log", next.histogramLog);
    double background[3] = {next.background[0], next.background[1], next.background[2]};
    view.numbers("background", background, 0.0, 1.0);
    for (int i = 0; i < 3; ++i) next.background[size_t(i)] = float(background[i]);

    const Section split(j, "split", name);
    split.boolean("enabled", next.split.enabled);
    split.integer("panes", next.split.imagePanes, 2, 4);
    if (next.split.imagePanes == 3) split.fail("panes", "expected 2 or 4");
    for (size_t i = 0; i < next.split.panes.size(); ++i) {
        const std::string pane(1, char('a' + i));
        split.name(("filter_" + pane).c_str(), next.split.panes[i].filter, &renderer::filterModeFromName);
        split.name(("compositing_" + pane).c_str(), next.split.panes[i].compositing, &renderer::compositingFromName);
    }
    // "difference": "off", "b" or "truth"; sessions before the truth pane wrote true (|A - B|) or false.
    const json* difference = j.contains("split") ? &j["split"] : nullptr;
    if (difference && difference->contains("difference") && (*difference)["difference"].is_boolean())
        next.split.difference = (*difference)["difference"].get<bool>() ? SplitDifference::AgainstB : SplitDifference::Off;
    else
        split.name("difference", next.split.difference, &splitDifferenceFromName);

    const Section slabs(j, "slabs", name);
    slabs.boolean("enabled", next.slabs.enabled);
    slabs.number("thickness", next.slabs.thickness, kSlabThicknessLo, kSlabThicknessHi);
    slabs.boolean("post_classified", next.slabs.postClassified);

    const Section mouse(j, "space_mouse", name);
    mouse.boolean("enabled", next.spaceMouse.enabled);
    mouse.number("speed", next.spaceMouse.speed, 0.01, 100.0);
    mouse.boolean("invert_rotation", next.spaceMouse.invertRotation);
    mouse.boolean("invert_moves", next.spaceMouse.invertTranslation);

    state = std::move(next);
    return volume;
}

} // namespace ui
