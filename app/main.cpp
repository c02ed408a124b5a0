// The splatlab command line: `render` and `info` run headless (EGL, no X server); `editor` opens the
// window. Errors from the renderer become one line on stderr and a non-zero exit.
#include "accuracy.h"
#include "cli_parse.h"
#include "compare_command.h"
#include "console_progress.h"
#include "editor.h"
#include "info_command.h"
#include "phantom_command.h"
#include "render_command.h"
#include "report_command.h"
#include "scene_flags.h"

#include "renderer/model/paraview_preset.h"
#include "renderer/model/transfer_function.h"
#include "renderer/oracle/demo_scenes.h"
#include "renderer/oracle/ground_truth.h"
#include "ui/editor_state.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <new>
#include <string>
#include <vector>

namespace {

using namespace renderer;



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

    RenderArgs ra;
    CLI::App* render = addRenderCommand(app, ra);

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
                                                 "framed, with --tf bonsai, lit per splat; a CT preset opens lit per splat "
                                                 "unless --shading says otherwise)");
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
        if (*render && !ra.scene.session.empty()) rejectFlagsBesideSession(render);
        if (*reference && !ref.session.empty()) rejectFlagsBesideSession(reference);
        if (*editor && !editorSession.empty()) rejectFlagsBesideSession(editor);
        if (*render) return runRender(ra);
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
        } else if (editorSession.empty() && e.sceneName.empty() && unset("--shading") && e.tfSpec.rfind("ct-", 0) == 0) {
            // A volume in a CT preset (the default ct-skin-bone, ct-bone, ...) shows surfaces: lit per
            // splat, as its user expects, unless --shading says otherwise. Unlit, a skull is a flat blob.
            editorLook.shading = "per-splat";
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
