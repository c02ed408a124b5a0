// The editor's window and main loop. Owns the GLFW window and its GL 4.5 core context, ImGui's
// backends, the loaded volume and the SplatRenderer; the ui panels only edit EditorState, and this file
// turns their edits into renders. Renderer calls happen outside the ImGui frame, so a throw from them
// never leaves ImGui half-way through a frame.
#include "editor.h"

#include "renderer/errors.h"
#include "renderer/oracle/filter_comparison.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/gl/gl_context.h"
#include "renderer/model/gradients.h"
#include "renderer/io/image.h"
#include "renderer/oracle/probe.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "renderer/io/volume_io.h"
#include "renderer/model/window.h"
#include "ui/dock_layout.h"
#include "ui/editor_state.h"
#include "ui/panels.h"
#include "ui/session.h"
#include "ui/space_mouse.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <deque>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

namespace {

std::string g_glfwError = "no message from GLFW"; // GLFW reports errors through a callback only

void onGlfwError(int code, const char* description) {
    char codeText[16];
    std::snprintf(codeText, sizeof codeText, "0x%05x", code);
    g_glfwError = std::string(description) + " (GLFW error " + codeText + ")";
}

// Files dropped on the window, oldest first; the frame loop opens one a frame (ui::dropFile). GLFW's
// drop callback carries no user data of ours, as the error callback.
std::deque<std::filesystem::path> g_dropped;

void onDrop(GLFWwindow*, int count, const char** paths) {
    for (int i = 0; i < count; ++i) g_dropped.emplace_back(paths[i]);
}

// glfwInit .. glfwTerminate and the window. Declared first in runEditor so it is destroyed last.
struct GlfwSession {
    GLFWwindow* window = nullptr;
    ~GlfwSession() {
        if (window) glfwDestroyWindow(window);
        glfwTerminate();
    }
};

// The ImGui context and its backends; shut down while the window and context still exist.
struct ImGuiSession {
    bool glfwBackend = false, glBackend = false;
    ~ImGuiSession() {
        if (glBackend) ImGui_ImplOpenGL3_Shutdown();
        if (glfwBackend) ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
};

// The volume's scene classified over `window`, with its gradients once they are computed.
renderer::SplatScene classifiedScene(const renderer::Volume& volume, const renderer::TransferFunction& tf,
                                     renderer::ValueRange window,
                                     const std::optional<renderer::GradientField>& gradients) {
    renderer::SplatScene scene = renderer::buildSplatScene(volume, tf, window);
    if (gradients) renderer::addGradients(scene, *gradients);
    return scene;
}

// The preview drawn while the view moves (ui::PreviewSettings): the volume at half resolution with its
// own scene and renderer, classified with the document's TF and window (the window of the full
// volume's values: the means span a narrower range).
struct Preview {
    renderer::Volume volume;
    renderer::SplatScene scene;
    renderer::SplatRenderer splats;
    std::optional<renderer::GradientField> gradients;

    explicit Preview(const renderer::Volume& full) : volume(renderer::halfResolution(full)) {}
    void classify(const renderer::TransferFunction& tf, renderer::ValueRange window) {
        renderer::SplatScene next = classifiedScene(volume, tf, window, gradients);
        splats.setScene(next);
        scene = std::move(next);
    }
    void setTransferFunction(const renderer::TransferFunction& tf) {
        renderer::setTransferFunction(scene, tf);
        splats.setLut(scene.lut);
    }
    // Once the full volume's gradients are ready; an eighth of the voxels, so computed right here.
    void addGradients() {
        gradients = renderer::computeGradients(volume);
        if (!gradients) return;
        renderer::addGradients(scene, *gradients);
        splats.setGradients(scene);
    }
};

// What the viewport shows. No volume (none given, or it failed to load) leaves `volume` empty.
struct Document {
    std::optional<renderer::Volume> volume;
    renderer::SplatScene scene;
    renderer::TransferFunction tf;          // what the scene was classified with
    renderer::Histogram histogram;          // of the whole volume, for the Window section
    renderer::ValueRange percentile;        // p1..p99
    std::optional<renderer::GradientField> gradients;   // once computed (for shading, a later issue)
    std::unique_ptr<Preview> preview;       // volumes of PreviewSettings::kMinVoxels or more
};

// Work on a worker thread that the UI thread polls each frame: its progress (0..1), a cancel flag the
// work's progress callback returns, and, once `done`, its result or the message of what it threw.
// Destroying the job cancels and joins it, so it must go before anything the work reads.
template <class T>
struct WorkerJob {
    std::thread thread;
    std::atomic<double> fraction{0.0};
    std::atomic<bool> cancel{false}, done{false};
    std::optional<T> result;   // written before `done`; empty when cancelled or failed
    std::string error;         // an exception from the worker, if any

    // `work(progress)` returns the result (or an optional of it); `progress(f)` returns false once cancelled.
    template <class Work>
    void start(Work work) {
        thread = std::thread([this, work] {
            try {
                result = work([this](double f) {
                    fraction = f;
                    return !cancel.load();
                });
            } catch (const std::exception& e) {
                error = e.what();
            }
            done = true;
        });
    }
    ~WorkerJob() {
        cancel = true;
        if (thread.joinable()) thread.join();
    }
};

// Gradients computed after a volume loads; the UI shows the progress modal meanwhile.
struct GradientJob : WorkerJob<renderer::GradientField> {
    explicit GradientJob(const renderer::Volume& volume) {
        start([&volume](const renderer::ProgressCallback& progress) { return renderer::computeGradients(volume, progress); });
    }
};

// A volume read on the worker: what the UI thread needs to show it (it makes the GL parts).
struct LoadedVolume {
    renderer::Volume volume;
    renderer::Histogram histogram;     // of the whole volume, for the Window section
    renderer::ValueRange percentile;   // p1..p99
    renderer::SplatScene scene;        // classified with the job's TF over its window
};

// Opening a volume: read, aligned to its world axes, its histogram taken and its scene classified on the
// worker, since a large scan takes seconds; the UI shows the progress modal meanwhile. Cancel stops the
// reading at once (volume_io.h), the rest between steps. The work holds its own copies: the
// job's members are gone before the base joins the thread.
struct VolumeJob : WorkerJob<LoadedVolume> {
    std::filesystem::path path;
    renderer::TransferFunction tf;
    VolumeJob(const std::filesystem::path& file, const std::optional<renderer::RawOptions>& raw,
              const renderer::TransferFunction& classify, const renderer::WindowSettings& window)
        : path(file), tf(classify) {
        start([file, raw, classify, window](const renderer::ProgressCallback& progress) -> std::optional<LoadedVolume> {
            LoadedVolume out;
            try {
                out.volume = renderer::loadVolumeInWorldFrame(file, raw,
                                                              [&](double f) { return progress(0.6 * f); });
            } catch (const renderer::Cancelled&) {
                return std::nullopt;
            }
            if (!progress(0.6)) return std::nullopt;
            out.histogram = renderer::computeHistogram(out.volume, 128);
            out.percentile = renderer::percentileWindow(out.volume, 1.0, 99.0);
            if (!progress(0.7)) return std::nullopt;
            out.scene = renderer::buildSplatScene(out.volume, classify, renderer::windowFor(out.volume, window));
            progress(1.0);
            return out;
        });
    }
};

// The Filters panel's "Measure": the ground truth of the view's centre crop on the worker (cached on
// disk), then, one filter a UI frame, each filter timed on the whole view and compared on the crop.
// It works on a copy of the scene: a TF edit changes the document's while the worker reads.
struct FilterComparisonJob {
    static constexpr std::array<renderer::FilterMode, 4> kFilters{
        renderer::FilterMode::Reconstruction, renderer::FilterMode::LowPass, renderer::FilterMode::Ewa,
        renderer::FilterMode::Adaptive};
    renderer::SplatScene scene;
    renderer::ImagePlane view, crop;
    renderer::SplatSettings settings;
    size_t measured = 0;                   // filters of kFilters measured so far
    WorkerJob<renderer::Image> truth;      // last: destroyed (joined) before the scene it reads

    FilterComparisonJob(const renderer::SplatScene& s, const renderer::ImagePlane& v, const renderer::SplatSettings& set)
        : scene(s), view(v), crop(renderer::centreCrop(v, renderer::kComparisonCropPx)), settings(set) {
        truth.start([this](const renderer::ProgressCallback& progress) {
            return renderer::cachedGroundTruth(scene, crop, settings, {}, renderer::defaultGroundTruthCacheDir(),
                                               progress);
        });
    }
};

// Dark theme: ImGui's dark colours with square docked windows and a little more air in the widgets.
void applyTheme() {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 0.0f;
    style.WindowBorderSize = 0.0f;
    style.FrameRounding = 3.0f;
    style.GrabRounding = 3.0f;
    style.TabRounding = 3.0f;
    style.PopupRounding = 3.0f;
    style.FramePadding = ImVec2(6, 4);
    style.ItemSpacing = ImVec2(8, 6);
    ImVec4* c = style.Colors;
    c[ImGuiCol_WindowBg] = ImVec4(0.105f, 0.110f, 0.125f, 1.0f);
    c[ImGuiCol_PopupBg] = ImVec4(0.130f, 0.135f, 0.150f, 0.98f);
    c[ImGuiCol_Separator] = ImVec4(0.25f, 0.26f, 0.30f, 1.0f);
    c[ImGuiCol_FrameBg] = ImVec4(0.17f, 0.18f, 0.21f, 1.0f);
    c[ImGuiCol_TitleBgActive] = c[ImGuiCol_TitleBg];
}

// The default framebuffer's back buffer as an opaque Image, row 0 at the top (GL's row 0 is the bottom).
renderer::Image readBackBuffer(int width, int height) {
    std::vector<unsigned char> bytes(size_t(width) * size_t(height) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
    renderer::checkGlErrors("editor screenshot");
    renderer::Image image(width, height);
    for (int y = 0; y < height; ++y) {
        const unsigned char* row = &bytes[size_t(height - 1 - y) * size_t(width) * 4];
        for (int x = 0; x < width; ++x) {
            float* p = image.pixel(x, y);
            for (int c = 0; c < 3; ++c)
                p[c] = float(row[x * 4 + c]) / 255.0f;
            p[3] = 1.0f; // the window is opaque; its alpha channel holds whatever blending left there
        }
    }
    return image;
}

} // namespace

int runEditor(const EditorOptions& options) {
    const bool scripted = options.frames > 0; // runs N frames and exits; errors end it with code 1

    // 1. Window with a GL 4.5 core context, made current; KHR_debug collects GL errors from here on.
    GlfwSession glfw;
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        std::fprintf(stderr, "splatlab editor: cannot open a window: %s (is DISPLAY set? try xvfb-run)\n",
                     g_glfwError.c_str());
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
#ifndef NDEBUG
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
    glfw.window = glfwCreateWindow(options.width, options.height, "SplatLab", nullptr, nullptr);
    if (!glfw.window) {
        std::fprintf(stderr,
                     "splatlab editor: cannot open a %dx%d window with an OpenGL 4.5 core context: %s\n",
                     options.width, options.height, g_glfwError.c_str());
        return 1;
    }
    glfwMakeContextCurrent(glfw.window);
    glfwSwapInterval(scripted ? 0 : 1);
    renderer::installGlDebugCallback();
    const std::string glRenderer = renderer::glRendererName();

    // 2. ImGui: context, dark theme, GLFW input and OpenGL3 drawing backends.
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiSession imgui;
    ImGui::GetIO().IniFilename = nullptr; // the layout is ours (ui::DockLayout), nothing to persist
    applyTheme();
    imgui.glfwBackend = ImGui_ImplGlfw_InitForOpenGL(glfw.window, true);
    glfwSetDropCallback(glfw.window, onDrop);
    imgui.glBackend = imgui.glfwBackend && ImGui_ImplOpenGL3_Init("#version 450");
    if (!imgui.glBackend) {
        std::fprintf(stderr, "splatlab editor: ImGui's GLFW/OpenGL3 backends failed to initialise on %s\n",
                     renderer::glVersionString().c_str());
        return 1;
    }

    // 3. Errors: scripted runs print one line and exit 1; interactive ones show the modal and go on.
    ui::EditorState state;
    int exitCode = 0;
    auto report = [&](const std::exception& error) {
        if (scripted) {
            std::fprintf(stderr, "splatlab editor: %s\n", error.what());
            exitCode = 1;
            glfwSetWindowShouldClose(glfw.window, GLFW_TRUE);
        } else {
            state.errorMessage = error.what();
        }
    };
    // Runs `step`, turning the renderer's typed errors into report(); returns whether it succeeded.
    auto guarded = [&](auto&& step) {
        try {
            step();
            return true;
        } catch (const renderer::LoadError& e) {
            report(e);
        } catch (const renderer::GlError& e) {
            report(e);
        } catch (const renderer::RenderError& e) {
            report(e);
        }
        return false;
    };

    // 4. Volume, transfer function, scene and renderer. A failure leaves the editor with no volume.
    //    Declared after the ImGui and GLFW sessions, so the renderer's GL objects go first.
    Document doc;
    std::unique_ptr<renderer::SplatRenderer> splats;
    std::unique_ptr<GradientJob> gradientJob;
    std::unique_ptr<VolumeJob> volumeJob;
    // Starts reading `path`, to be classified with state.tf over state.window, on the worker (a scripted
    // run waits for it: deterministic frames); the frame loop shows it once read (showVolume).
    auto openVolume = [&](const std::filesystem::path& path, const std::optional<renderer::RawOptions>& raw = {}) {
        volumeJob = std::make_unique<VolumeJob>(path, raw, state.tf, state.window);
        if (scripted) volumeJob->thread.join();
    };
    // A volume read by a VolumeJob, on screen: a new document and the renderer's scene (and the preview's,
    // GL objects made on this thread); its gradients start on the worker. On failure the document shown
    // stays.
    auto showVolume = [&](LoadedVolume loaded, const std::filesystem::path& path, const renderer::TransferFunction& tf) {
        return guarded([&] {
            Document next;
            next.tf = tf;
            next.histogram = std::move(loaded.histogram);
            next.percentile = loaded.percentile;
            next.scene = std::move(loaded.scene);
            if (loaded.volume.voxelCount() >= ui::PreviewSettings::kMinVoxels) {
                next.preview = std::make_unique<Preview>(loaded.volume);
                next.preview->classify(next.tf, next.scene.window);
            } else if (options.preview) {
                std::fprintf(stderr,
                             "note: --preview: %s has %zu voxels, fewer than the %zu M that get a preview; it "
                             "renders in full\n",
                             path.string().c_str(), loaded.volume.voxelCount(), ui::PreviewSettings::kMinMegaVoxels);
            }
            next.volume = std::move(loaded.volume);
            auto fresh = splats ? nullptr : std::make_unique<renderer::SplatRenderer>();
            (splats ? *splats : *fresh).setScene(next.scene);
            if (fresh) splats = std::move(fresh);
            gradientJob.reset();   // cancels the gradients of the volume going away
            doc = std::move(next);
            state.preview.available = doc.preview != nullptr;
            state.gradientsReady = false;
            state.loadedVolume = path;
            state.volumeFile = path.string();
            glfwSetWindowTitle(glfw.window, ("SplatLab \xE2\x80\x94 " + path.stem().string()).c_str());
            gradientJob = std::make_unique<GradientJob>(*doc.volume);
            if (scripted) gradientJob->thread.join();
        });
    };
    std::filesystem::path volumePath = options.volumePath;
    guarded([&] {
        state.camera = options.camera;
        state.camera.up = renderer::axisFromName(options.upAxis);
        state.settings = options.settings;
        state.showHeatmap = options.settings.heatmap;
        state.window = options.window;
        state.perf.renderContinuously = options.continuous || options.spinDegPerS != 0.0;
        if (!(std::abs(options.spinDegPerS) <= 90.0))
            throw renderer::RenderError("--spin takes -90 to 90 degrees a second, got " +
                                        std::to_string(options.spinDegPerS));
        state.perf.spinDegPerS = options.spinDegPerS;
        state.tf = renderer::transferFunctionFromSpec(options.tfSpec);
        if (options.sessionPath.empty()) return;
        // The session replaces what the flags set; a volume argument replaces the session's volume.
        const std::filesystem::path sessionVolume = ui::loadSession(options.sessionPath, state);
        state.sessionFile = options.sessionPath.string();
        if (volumePath.empty()) volumePath = sessionVolume;
    });
    if (exitCode == 0 && !volumePath.empty()) openVolume(volumePath, options.raw);
    if (exitCode != 0) return exitCode;

    // 5. Frame loop. Edits made in frame N are rendered at the top of frame N+1, at the viewport size
    //    frame N measured; the first frame only measures.
    ui::DockLayout layout = ui::makeEditorLayout();
    ui::SettingsChanges settingsChanges;
    ui::ViewportResult viewport;
    unsigned texture = 0; // the renderer's display texture; 0 until something was rendered
    int renderWidth = 0, renderHeight = 0;
    bool tfPending = false, renderPending = true, windowChanged = false, tfChanged = false;
    bool framePending = options.fit;   // --fit, Settings > Camera > Frame or a double-click: framedCamera()
    // The Performance panel: recent renders; back to back: this UI frame follows one that rendered.
    ui::PerfHistory perfHistory;
    std::optional<std::chrono::steady_clock::time_point> lastRenderStart;
    bool renderedLastFrame = false;
    // The Filters panel: the last render's view, and the patches per filter the classifier gives it
    // (read back from the GPU after a render, while the panel is shown).
    std::optional<renderer::ImagePlane> lastPlane;
    std::optional<std::array<uint64_t, 3>> patchCounts;
    bool filtersShown = false, patchCountsStale = true;
    ui::FiltersChanges filtersChanges;
    std::unique_ptr<FilterComparisonJob> comparison;
    // A new window re-classifies every voxel, the preview's too; the scenes keep the old one if this throws.
    // While the window is dragged only the preview's are (fullWindowStale), and this follows.
    bool windowDragged = false, fullWindowStale = false;
    auto reclassify = [&] {
        fullWindowStale = false;
        renderPending = true;
        guarded([&] {
            const renderer::ValueRange window = renderer::windowFor(*doc.volume, state.window);
            renderer::SplatScene scene = classifiedScene(*doc.volume, doc.tf, window, doc.gradients);
            splats->setScene(scene);
            doc.scene = std::move(scene);
            if (doc.preview) doc.preview->classify(doc.tf, window);
        });
    };
    // The window the view is classified with: the preview's while a drag has left the full scene's behind.
    auto shownWindow = [&] { return fullWindowStale && doc.preview ? doc.preview->scene.window : doc.scene.window; };
    // Renders the view into `texture`, the preview's renderer or the full one; false if it threw.
    auto renderView = [&](bool preview) {
        return guarded([&] {
            const renderer::ImagePlane plane = renderer::makeImagePlane(
                state.camera, doc.scene.centre, doc.scene.radius, renderWidth, renderHeight, doc.scene.axes);
            // Shading waits for the gradients (computed after a volume loads); until then, unshaded.
            renderer::SplatSettings drawn = state.settings;
            if (!state.gradientsReady) drawn.shading = renderer::SplatSettings::Shading::None, drawn.surfaceFlatten = 1.0;
            state.preview.shown = preview;
            if (preview) {   // the same extinction per unit length from voxels twice the size
                drawn.density = renderer::densityFor(doc.preview->volume, *doc.volume, drawn.density);
                doc.preview->splats.render(plane, drawn);
                texture = doc.preview->splats.displayTexture(state.background.data(), state.showHeatmap);
                return;
            }
            splats->render(plane, drawn);
            texture = splats->displayTexture(state.background.data(), state.showHeatmap);
            lastPlane = plane;
            patchCountsStale = true;
        });
    };
    // Settings > Files > Save image (and --save-image): the view as the viewport shows it, at its size.
    // Returns what was written ("955 x 545 (heatmap)"), or nothing after reporting the failure.
    auto saveView = [&](const std::filesystem::path& path) -> std::optional<std::string> {
        std::optional<std::string> written;
        guarded([&] {
            if (!splats || texture == 0)
                throw renderer::LoadError(path.string(), "", "no view to save: open a volume first");
            const bool behind = fullWindowStale || state.preview.shown;   // the full renderer lacks this view
            if (fullWindowStale) reclassify();
            if (behind && !renderView(false)) return;
            const renderer::Image image = state.showHeatmap ? splats->readbackHeatmap() : splats->readback();
            renderer::writeImage(image, path, state.background.data());
            written = std::to_string(image.width) + " x " + std::to_string(image.height) +
                      (state.showHeatmap ? " (heatmap)" : "");
            state.imageSaved = "wrote " + path.filename().string() + ", " + *written;
        });
        return written;
    };
    // What the Performance panel's figures are of, for its Copy: volume, image size, mode, GL_RENDERER.
    auto perfContext = [&] {
        if (!doc.volume || !lastPlane || !splats) return "no volume, " + glRenderer;
        return ui::renderContext(doc.volume->name, doc.volume->dims, {lastPlane->width, lastPlane->height},
                                 state.settings, splats->stats(), glRenderer);
    };
    std::vector<renderer::FilterMeasurement> measurements;
    bool measurementsStale = false;
    const std::vector<ui::DockPanel> panels = {
        {"Transfer function", "left",
         [&] {
             tfChanged = ui::drawTransferFunctionPanel(
                 state, {.histogram = doc.volume ? &doc.histogram : nullptr, .window = shownWindow()});
             windowChanged = ui::drawWindowSection(state, {.volume = doc.volume ? &*doc.volume : nullptr,
                                                           .histogram = &doc.histogram,
                                                           .percentile = doc.percentile,
                                                           .window = shownWindow()});
         }},
        {"Settings", "left", [&] { settingsChanges = ui::drawSettingsPanel(state); }},
        {"Viewport", "viewport", [&] { viewport = ui::drawViewportPanel(state, texture); }},
        {"Stats", "bottom",
         [&] {
             const bool preview = state.preview.shown && doc.preview;   // the figures of what the viewport shows
             ui::drawStatsPanel({.frame = preview ? doc.preview->splats.stats()
                                          : splats ? splats->stats() : renderer::FrameStats{},
                                 .volume = doc.volume ? &*doc.volume : nullptr,
                                 .visibleSplats = (preview ? doc.preview->scene : doc.scene).visibleCount(),
                                 .sceneBytes = preview ? doc.preview->splats.sceneBytes() : splats ? splats->sceneBytes() : 0,
                                 .workingBytes = preview ? doc.preview->splats.workingBytes()
                                                 : splats ? splats->workingBytes() : 0,
                                 .glRenderer = glRenderer});
         }},
        {"Performance", "bottom", [&] { ui::drawPerformancePanel(state, perfHistory, perfContext); }},
        {"Filters", "bottom",
         [&] {
             filtersShown = true;
             filtersChanges =
                 ui::drawFiltersPanel(state, {.plane = lastPlane && doc.volume ? &*lastPlane : nullptr,
                                              .dims = doc.scene.dims,
                                              .origin = doc.scene.origin,
                                              .spacing = doc.scene.spacing,
                                              .radius = doc.scene.radius,
                                              .frame = splats ? splats->stats() : renderer::FrameStats{},
                                              .patches = patchCounts,
                                              .measurements = measurements,
                                              .cropPx = renderer::kComparisonCropPx,
                                              .measuring = comparison != nullptr,
                                              .measurementsStale = measurementsStale,
                                              .truthProgress = comparison ? comparison->truth.fraction.load() : 0.0});
         }},
        {"Help", "bottom", [] { ui::drawHelpPanel(); }},
    };
    for (const std::string& tab : options.tabs)
        if (std::none_of(panels.begin(), panels.end(), [&](const ui::DockPanel& p) { return p.title == tab; })) {
            std::string titles;
            for (const ui::DockPanel& p : panels) titles += (titles.empty() ? "" : ", ") + p.title;
            std::fprintf(stderr, "splatlab: --tab: no panel called '%s' (panels: %s)\n", tab.c_str(), titles.c_str());
            return 1;
        }

    // A 3D mouse, if one is plugged in. Scripted runs show its status but never move with it: their
    // frames stay reproducible.
    ui::SpaceMouse spaceMouse(ui::makeHidapiBackend());
    double lastPoll = glfwGetTime(), lastSpin = lastPoll;
    auto knobDeflected = [&] {
        return !scripted && spaceMouse.connected() && state.spaceMouse.enabled && spaceMouse.state().deflected();
    };

    for (int frame = 1; !glfwWindowShouldClose(glfw.window); ++frame) {
        // Idle: sleep until an event (or 50 ms for the GPU timer, 16 ms to read a 3D mouse); busy,
        // scripted or the knob deflected: keep going.
        if (scripted || renderPending || tfPending || knobDeflected() || state.perf.renderContinuously) glfwPollEvents();
        else glfwWaitEventsTimeout(spaceMouse.connected() ? 0.016 : 0.05);
        if (splats) {
            splats->collectTimers();
            perfHistory.addTimes(splats->stats());
        }
        const double pollTime = glfwGetTime();
        spaceMouse.poll(pollTime);
        state.spaceMouseStatus = spaceMouse.status();
        if (knobDeflected() && ui::applyOrbitInput(state.camera, ui::spaceMouseOrbit(spaceMouse.state(),
                                                                                     pollTime - lastPoll,
                                                                                     state.spaceMouse))) {
            renderPending = true;
            state.preview.lastInput = pollTime;
        }
        lastPoll = pollTime;

        // 5a. Renderer work for last frame's edits. A failed step waits for the next edit instead of
        //     repeating (and re-opening the error modal) every frame.
        if (volumeJob && volumeJob->done) {   // a volume read: show it, or say why it could not be
            if (volumeJob->thread.joinable()) volumeJob->thread.join();
            const std::unique_ptr<VolumeJob> job = std::move(volumeJob);
            if (!job->error.empty()) report(std::runtime_error(job->error));
            else if (job->result && showVolume(std::move(*job->result), job->path, job->tf)) renderPending = true;
        }
        if (settingsChanges.openVolume) {
            openVolume(state.volumeFile);
            renderPending = true;
        }
        if (settingsChanges.saveImage) saveView(state.imageFile);
        if (settingsChanges.sessionOpened) {
            // Another volume: load it with the session's window and TF; the same one: re-classify it.
            const std::filesystem::path& v = settingsChanges.sessionVolume;
            std::error_code ec;
            if (!v.empty() && !std::filesystem::equivalent(v, state.loadedVolume, ec)) openVolume(v);
            else tfPending = windowChanged = true;
            renderPending = true;
        }
        if (splats && tfPending) {
            tfPending = false;
            guarded([&] {
                doc.tf = state.tf;
                renderer::setTransferFunction(doc.scene, doc.tf);
                splats->setLut(doc.scene.lut);   // the lists stay; only the LUT travels
                if (doc.preview) doc.preview->setTransferFunction(doc.tf);
            });
        }
        if (splats && windowChanged) {
            windowChanged = false;
            renderPending = true;
            if (windowDragged && doc.preview && state.preview.whileMoving) {   // the preview's eighth of the voxels now
                guarded([&] { doc.preview->classify(doc.tf, renderer::windowFor(*doc.volume, state.window)); });
                fullWindowStale = true;
            } else {
                reclassify();
            }
        }
        if (fullWindowStale && !(state.preview.whileMoving && state.preview.moving(pollTime)))
            reclassify();   // every voxel once the drag settles (or the preview is turned off)
        if (gradientJob && gradientJob->done) {
            if (gradientJob->thread.joinable()) gradientJob->thread.join();
            doc.gradients = std::move(gradientJob->result);
            if (!gradientJob->error.empty()) state.errorMessage = "gradients: " + gradientJob->error;
            gradientJob.reset();
            if (splats && doc.gradients) {   // shading and surface splats become available
                guarded([&] {
                    renderer::addGradients(doc.scene, *doc.gradients);
                    splats->setGradients(doc.scene);   // the rest of the scene is on the GPU already
                    if (doc.preview) doc.preview->addGradients();
                    state.gradientsReady = true;
                });
                renderPending = true;
            }
        }
        // The Filters panel's measurement: start it, cancel it, or measure one more filter.
        if (filtersChanges.cancel) comparison.reset();
        if (filtersChanges.measure && splats && lastPlane && !comparison) {
            measurements.clear();
            measurementsStale = false;
            comparison = std::make_unique<FilterComparisonJob>(doc.scene, *lastPlane, state.settings);
        }
        if (comparison && comparison->truth.done) {
            if (comparison->truth.thread.joinable()) comparison->truth.thread.join();
            if (!comparison->truth.error.empty()) {
                state.errorMessage = "measuring the filters: " + comparison->truth.error;
                comparison.reset();
            } else if (comparison->measured < FilterComparisonJob::kFilters.size()) {
                guarded([&] {
                    measurements.push_back(renderer::measureFilter(
                        *splats, comparison->view, comparison->crop, *comparison->truth.result, comparison->settings,
                        FilterComparisonJob::kFilters[comparison->measured++], 3));
                });
                renderPending = true;   // re-rendered below: the crop replaced the view's targets
            } else {
                comparison.reset();
            }
        }
        // Framing needs the viewport's aspect, known from the first frame on, and the scene's current LUT.
        // No volume, none being read: nothing to frame. One being read: framed once it is shown.
        framePending = (framePending || settingsChanges.frame || viewport.frame) && (splats || volumeJob);
        if (framePending && renderWidth > 0 && !volumeJob) {
            framePending = false;
            state.camera = renderer::framedCamera(state.camera, doc.scene, state.settings, renderWidth, renderHeight,
                                                  ui::kMinDistance, ui::kMaxDistance);
            renderPending = true;
        }
        // Continuous rendering (Performance panel): every frame renders, turning the camera if asked
        // (scripted runs turn by a fixed 1/60 s a frame, so their pictures stay reproducible).
        const bool continuous = state.perf.renderContinuously && state.errorMessage.empty();
        if (continuous && state.perf.spinDegPerS != 0.0) {
            const double dt = scripted ? 1.0 / 60.0 : std::min(pollTime - lastSpin, 0.1);
            ui::applyOrbitInput(state.camera,
                                {.rotateDxPx = float(-state.perf.spinDegPerS * dt / ui::kOrbitDegPerPx)});
            comparison.reset();   // a turning view has no measurement to take
            measurementsStale = true;
        }
        lastSpin = pollTime;
        renderPending |= continuous;
        // While the view moves, the preview; once it settles, the full render.
        const bool preview = doc.preview && state.preview.whileMoving && (options.preview || state.preview.moving(pollTime));
        renderPending |= state.preview.shown && !preview;
        const bool renderNow = splats && renderPending && renderWidth > 0;
        if (renderNow) {
            renderPending = false;
            const auto start = std::chrono::steady_clock::now();
            const double intervalMs =
                renderedLastFrame && lastRenderStart
                    ? std::chrono::duration<double, std::milli>(start - *lastRenderStart).count()
                    : 0.0;
            lastRenderStart = start;
            if (!renderView(preview)) texture = 0;
            else if (!preview) perfHistory.addRender(splats->stats(), intervalMs);   // the Performance panel's figures are of full renders
        }
        renderedLastFrame = renderNow;
        if (splats && lastPlane && filtersShown && patchCountsStale) {
            patchCountsStale = false;
            guarded([&] {
                renderer::SplatSettings adaptive = state.settings;
                adaptive.filter = renderer::FilterMode::Adaptive;
                std::array<uint64_t, 3> counts{};
                for (uint8_t mode : splats->patchModes(*lastPlane, adaptive)) ++counts[std::min<size_t>(mode, 2)];
                patchCounts = counts;
            });
        }

        // 5b. The UI: layout, panels, error modal.
        state.openingVolume = volumeJob ? volumeJob->path : std::filesystem::path();
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        settingsChanges = {};
        tfChanged = windowChanged = filtersShown = false;
        filtersChanges = {};
        viewport.cameraChanged = viewport.frame = false;
        std::vector<std::string> tabsToFront = frame <= 2 ? options.tabs : std::vector<std::string>{};
        if (!g_dropped.empty()) {   // its panel opens it as its button would (and shows its errors)
            tabsToFront.push_back(ui::dropFile(state, g_dropped.front()));
            g_dropped.pop_front();
        }
        ui::drawDockSpace(layout, panels, tabsToFront);
        ui::drawErrorModal(state);
        if (ui::drawProgressModal("Opening volume",
                                  volumeJob ? "Reading " + volumeJob->path.filename().string() +
                                                  (volumeJob->cancel ? " (cancelling)" : "")
                                            : std::string(),
                                  volumeJob ? volumeJob->fraction.load() : 1.0, volumeJob != nullptr))
            volumeJob->cancel = true;
        // One modal at a time: the gradients of the volume shown go on under a volume being read.
        if (ui::drawProgressModal("Computing gradients",
                                  "Gradients of " + (doc.volume ? doc.volume->name : std::string()) +
                                      " (central differences, all cores)",
                                  gradientJob ? gradientJob->fraction.load() : 1.0, gradientJob && !volumeJob))
            gradientJob->cancel = true;
        ImGui::Render();
        // The voxel under the mouse, for the next frame's tooltip and TF marker: the last full render's
        // view, so not while a drag shows the preview or a window edit left the full scene behind.
        state.probe.reset();
        if (viewport.hoverPx && lastPlane && doc.volume && !fullWindowStale && !state.preview.shown)
            if (const auto hit = renderer::probePixel(doc.scene, state.settings, *lastPlane, *viewport.hoverPx))
                state.probe = ui::EditorState::ProbedVoxel{hit->voxel, doc.volume->at(hit->voxel.x, hit->voxel.y, hit->voxel.z)};
        tfPending |= tfChanged;
        // Any edit of the view ends a measurement under way and dates the last one.
        const bool viewEdited = settingsChanges.any() || tfChanged || windowChanged || filtersChanges.settingsChanged ||
                                viewport.cameraChanged || settingsChanges.openVolume || settingsChanges.sessionOpened ||
                                settingsChanges.frame || viewport.frame;
        if (viewEdited) {
            comparison.reset();
            measurementsStale = true;
        }
        const bool mouseDown = ImGui::IsMouseDown(ImGuiMouseButton_Left);
        windowDragged = windowChanged && mouseDown;
        if (viewport.cameraChanged || ((tfChanged || windowChanged) && mouseDown))
            state.preview.lastInput = glfwGetTime();   // a drag or the wheel: the preview until it settles
        renderPending |= viewEdited;
        if (viewport.widthPx != renderWidth || viewport.heightPx != renderHeight) {
            renderWidth = viewport.widthPx, renderHeight = viewport.heightPx;
            renderPending = true;
        }

        // 5c. Draw the UI into the back buffer; a scripted run's last frame is the screenshot.
        int fbWidth = 0, fbHeight = 0;
        glfwGetFramebufferSize(glfw.window, &fbWidth, &fbHeight);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fbWidth, fbHeight);
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        guarded([] { renderer::checkGlErrors("editor frame"); });
        if (scripted && frame >= options.frames && exitCode == 0) {
            if (!options.saveImagePath.empty()) {
                if (const auto written = saveView(options.saveImagePath))
                    std::printf("wrote %s, %s\n", options.saveImagePath.string().c_str(), written->c_str());
            }
            if (!options.screenshotPath.empty() && fbWidth > 0 && fbHeight > 0 && guarded([&] {
                    renderer::writeImage(readBackBuffer(fbWidth, fbHeight), options.screenshotPath);
                }))
                std::printf("wrote %s\n", options.screenshotPath.string().c_str());
            glfwSetWindowShouldClose(glfw.window, GLFW_TRUE);
        }
        glfwSwapBuffers(glfw.window);

    }
    return exitCode;
}
