// The editor between frames: the document, the renderer, the worker jobs and what the panels edited, with
// the steps of one frame that runEditor (editor.cpp) calls in order. The ui panels only edit EditorState;
// these steps turn their edits into renders, outside the ImGui frame, so a throw from the renderer never
// leaves ImGui half-way through a frame.
#pragma once
#include "editor.h"
#include "editor_document.h"
#include "editor_jobs.h"
#include "editor_window.h"
#include "interactive_probe.h"
#include "preset_gallery.h"
#include "render_thread.h"
#include "split_truth.h"
#include "view_texture.h"

#include "renderer/errors.h"
#include "renderer/out_of_memory.h"
#include "ui/dock_layout.h"
#include "ui/editor_state.h"
#include "ui/panels.h"
#include "ui/space_mouse.h"

#include <array>
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

class EditorLoop {
  public:
    // Needs the window open, its context current and ImGui on it; both outlive the loop. Starts the render
    // thread with its own GL context; throws GlError when it has none.
    EditorLoop(const EditorOptions& options, EditorWindow& window);
    EditorLoop(const EditorLoop&) = delete;
    EditorLoop& operator=(const EditorLoop&) = delete;

    // == Before the first frame (editor_loop.cpp)
    // The flags, then the session file they name; the volume starts loading. False after an error.
    bool start();
    // --tab names panels that exist; false after printing which do.
    bool checkTabs() const;
    // A 3D mouse, if one is plugged in; the clocks of its input and of the spin start here.
    void connectSpaceMouse();

    // == One frame, in this order. Edits made in frame N are rendered at the top of frame N+1, at the
    //    viewport size frame N measured; the first frame only measures.
    void waitForInput();          // editor_loop.cpp: events, GPU timers, the 3D mouse
    void applyEdits();            // editor_edits.cpp: volumes read, session, TF, window, gradients
    void stepFilterMeasurement(); // editor_viewport.cpp: the Filters panel's Measure, a setting a frame
    void renderViewport();        // editor_viewport.cpp: framing, spin, the render, patch counts
    void drawPanels(int frame);   // editor_panels.cpp: the ImGui frame (layout, panels, modals)
    void noteEdits();             // editor_panels.cpp: the probe; what the edits ask next frame
    void presentFrame(int frame); // editor_loop.cpp: the UI into the back buffer; a scripted run's outputs

    int exitCode() const { return m_exitCode; } // 0, or 1 after a scripted run's error
    // Keeps the dock layout (open panels, their docks, split sizes) in the config folder for the next run.
    void saveLayout();
    // --session-out: what the editor shows, as Settings > Session > Save writes it; prints what it wrote.
    void saveSessionTo(const std::filesystem::path& file);

  private:
    // == Errors (editor_loop.cpp): scripted runs print one line and exit 1; interactive ones show the modal
    // and go on.
    void report(const std::exception& error);
    // Runs `step`, turning the renderer's typed errors into report(); returns whether it succeeded.
    template <class Step> bool guarded(Step&& step);

    // == Volumes and scenes (editor_edits.cpp)
    // Starts reading `path`, to be classified with state.tf over state.window, on the worker (a scripted
    // run waits for it: deterministic frames); the frame loop shows it once read (showVolume).
    void openVolume(const std::filesystem::path& path, const std::optional<renderer::RawOptions>& raw = {});
    // A demo scene (renderer/oracle/demo_scenes.h): its volume opened, and as asked its look (TF over the
    // data range, density 1, unlit) and its view, placed once the viewport's height is known (the board's
    // view is panned in pixels).
    void openDemoScene(const std::string& name, bool withLook, bool withCamera);
    // A volume read by a VolumeJob, on screen: a new document, its scenes (the full one's and the preview
    // level's) handed to the render thread; its gradients start on the worker. On failure the document
    // shown stays.
    bool showVolume(LoadedVolume loaded, const std::filesystem::path& path,
                    const renderer::TransferFunction& tf);
    // A new window re-classifies every voxel, the levels' too, on the worker (scripted runs wait for it);
    // while the window is dragged only the levels' (m_fullWindowStale), and the full scene once it
    // settles. A classification asked while one runs starts when it ends (the last one asked).
    void reclassify(bool levelsOnly);
    void takeClassified(); // a classification done: its scenes into the document and to the render thread
    void classifyNow();    // Save image: the full scene classified with the window on screen, waiting for it
    // The window the view is classified with: the preview's while a drag has left the full scene's behind.
    renderer::ValueRange shownWindow() const;
    void takeLoadedVolume();      // a volume read: show it, or say why it could not be
    void applySettingsActions();  // Settings: open a volume, save the image, a session opened
    void applyTransferFunction(); // the TF edited: only the LUT travels
    void applyWindow();           // the window edited: re-classify (the preview's only, while dragged)
    void takeGradients();         // gradients computed: shading and surface splats become available

    // == The view (editor_viewport.cpp)
    // What the render thread is asked to draw for the view as it stands.
    ViewRequest viewRequest() const;
    // The slab frame a still view ends in (Settings > Image-aligned slabs), where it can have one.
    std::optional<renderer::SlabOptions> slabsOfView() const;
    void noteSlabStatus(); // the section's status: drawing, shown (showRenderedView), or why not
    // The level a far view needs (ViewRequest::finestLevel): the coarsest preview level whose kernels take
    // the low-pass filter (renderer/model/detail_levels.h), with hysteresis against the last request's.
    int farViewLevel(const ViewRequest& request);
    // Settings > Files > Save image (and --save-image): the view as the viewport shows it, at its size,
    // rendered in full on the render thread; finishSaveView writes it once there (wait: at once).
    void startSaveView(const std::filesystem::path& path);
    // The split view saved: its panes in their layout (ui::splitLayout), and the difference's figures.
    struct SplitImage {
        renderer::Image panes;
        std::optional<ui::DifferencePane> difference;
        std::string against = "B"; // |A - B| or |A - truth|
        std::string truthOf;       // " against the truth at 79x68 (coarse, upsampled)"
    };
    std::future<SplitImage> startSaveSplitView(const ViewRequest& view);
    std::string splitSavedText(const SplitImage& split) const; // " (split: A ... | B ... | |A - B| RMSE ...)"

    // == The split view (editor_split.cpp)
    void splitViewRequest(ViewRequest& request) const; // each pane's settings, at the pane's size
    void showSplitPanes(RenderedView& view);           // the other and difference panes into textures
    // |A - ground truth|: the truth of the view wanted (split_truth.h), and the difference of the A image
    // shown against the truth of that same view (scripted runs wait for the full truth).
    void stepSplitTruth();
    std::string truthLabel() const; // "|A - truth|, truth at 318x272"
    std::vector<ui::ViewportPane> splitPanes() const;  // what the viewport lays out (none: one image)
    // The pointer over the viewport in the view's pixels: in a split view, within the pane it is over.
    std::optional<glm::dvec2> pointerInPane() const;
    // Returns what was written ("955 x 545 (heatmap)"), or nothing (not yet, or after reporting the failure).
    std::optional<std::string> finishSaveView(bool wait);
    void frameIfAsked();        // --fit, Settings > Camera > Frame or a double-click: framedCamera()
    void spinIfContinuous();    // the Performance panel's continuous rendering, turning if asked
    void tourIfRunning();       // the Filters panel's regime tour: the camera's distance this frame
    void renderIfPending();     // asks the render thread for the view (scripted runs wait for it)
    void showRenderedView();    // the newest finished image into the viewport's texture
    void countPatchesIfShown(); // the Filters panel's patches per filter
    void drawGalleryIfOpen();   // the TF panel's Gallery: the next preset's thumbnail (preset_gallery.h)
    int thumbnailLevel() const;                      // 0: the full scan, k: the preview's level k
    const renderer::SplatScene& thumbnailScene(int level) const; // that level's scene
    ThumbnailSource thumbnailSource(int level) const; // what the gallery draws its thumbnails from
    void takeRenderErrors();    // what the render thread failed at, reported

    // == The panels (editor_panels.cpp)
    std::vector<ui::DockPanel> makePanels();
    // The heatmap texture and the legend of the view shown, while the heatmap is on.
    ui::ViewportOverlay viewportOverlay() const;
    // What the Performance panel's figures are of, for its Copy: volume, image size, mode, GL_RENDERER.
    std::string perfContext() const;
    // The Stats panel's levels: which is on screen, each one's last time and error against the full frame.
    std::string levelsText() const;
    void probeHoveredVoxel();

    // == Input and output (editor_loop.cpp)
    bool knobDeflected() const; // the 3D mouse moves the camera this frame
    // A scripted run's last frame: --save-image and --screenshot (the back buffer just drawn), then close.
    void writeScriptedOutputs(int fbWidth, int fbHeight);

    // Members go in reverse order of declaration: each job before what it reads, the renderer's GL
    // objects before the window's context (the window outlives this loop).
    const EditorOptions& m_options;
    EditorWindow& m_window;
    const bool m_scripted; // runs N frames and exits; errors end it with code 1
    std::string m_glRenderer; // the render thread's GL_RENDERER
    ui::EditorState m_state;
    int m_exitCode = 0;

    // Volume, transfer function, scene and renderer. A failure leaves the editor with no volume.
    Document m_doc;
    std::unique_ptr<RenderThread> m_render; // owns the renderers and their GL context
    bool m_hasScene = false;                // a scene was handed to the render thread
    std::unique_ptr<GradientJob> m_gradientJob;
    std::unique_ptr<ClassifyJob> m_classifyJob; // reads m_doc: declared after it, so it goes first
    std::optional<bool> m_classifyNext;         // asked while one ran: levels only?
    std::unique_ptr<VolumeJob> m_volumeJob;

    // What the panels returned last frame, read by this frame's steps.
    ui::DockLayout m_layout = ui::makeEditorLayout();
    ui::SettingsChanges m_settingsChanges;
    ui::ViewportResult m_viewport;
    ViewTexture m_image;   // the viewport's image (the last finished one)
    ViewTexture m_heatmap; // and its heatmap, when the heatmap is on
    bool m_shownHasHeatmap = false; // the image shown came with its heatmap (m_heatmap holds it)
    // The split view: the other panes' images (B, C, D) and the difference pane's (split_view.h), and how
    // many image panes the image shown has (1: no split).
    std::array<ViewTexture, 3> m_otherImages;
    ViewTexture m_differenceImage;
    int m_shownPanes = 1;
    // |A - truth|: the truth's worker; the scene's version (a new volume, TF, window or gradients), which
    // its key holds; the difference shown, of (the request of the A image, the truth's computed size).
    std::unique_ptr<SplitTruth> m_truth;
    uint64_t m_sceneVersion = 0;
    std::string m_truthUnavailable; // why there is no truth for these settings ("": there is)
    struct TruthDifference {
        std::tuple<uint64_t, int, int> of;
        std::string key;
        std::shared_ptr<const renderer::Image> truth;
        bool coarse = false;
        ui::DifferencePane pane; // its figures (the pixels are in m_differenceImage)
        double seconds = 0.0;
        bool cached = false;
    };
    std::optional<TruthDifference> m_truthDifference;
    int m_renderWidth = 0, m_renderHeight = 0;
    std::optional<RenderedView> m_shown;    // what the viewport shows (its pixels dropped once uploaded)
    uint64_t m_viewRequest = 0;             // the last view asked for
    bool m_slabsAsked = false;              // ...with a slab frame
    int m_farLevel = 0;                     // its finestLevel
    // Each preview level's optical mass change against the full scene, of scene version m_levelMassOf.
    std::vector<double> m_levelMassChange;
    uint64_t m_levelMassOf = ~uint64_t(0);
    struct PendingSave {
        std::filesystem::path path;
        double heatmapOpacity = 0.0;   // the heatmap over the image, as the viewport blends it
        std::future<std::pair<renderer::Image, renderer::Image>> images;   // image, heatmap (0 x 0: none)
        std::future<SplitImage> split;                                     // instead, in a split view
        bool slabs = false;                                                // the image is the slab frame
    };
    std::optional<PendingSave> m_save;
    std::optional<std::future<std::vector<uint8_t>>> m_patchModes;
    std::optional<std::future<renderer::FilterMeasurement>> m_measurement;
    bool m_tfPending = false, m_renderPending = true, m_windowChanged = false, m_tfChanged = false;
    bool m_framePending; // --fit, Settings > Camera > Frame or a double-click: framedCamera()
    std::optional<std::string> m_sceneCameraPending; // a demo scene's view, placed as framing is
    // The Performance panel: recent full frames; the interval between them while rendering continuously.
    ui::PerfHistory m_perfHistory;
    std::optional<std::chrono::steady_clock::time_point> m_lastFullFrame;
    // The Filters panel: the last render's view, and the patches per filter the classifier gives it
    // (computed on the render thread after a full frame, while the panel is shown).
    std::optional<renderer::ImagePlane> m_lastPlane;
    std::optional<std::array<uint64_t, 3>> m_patchCounts;
    // The TF panel's Gallery: its thumbnails are of the volume shown (the count of volumes shown so far),
    // the window and whether shading could be on; any change draws them again.
    PresetGallery m_gallery;
    uint64_t m_volumesShown = 0;
    std::optional<std::tuple<uint64_t, float, float, bool>> m_galleryOf;
    bool m_filtersShown = false, m_patchCountsStale = true;
    ui::FiltersChanges m_filtersChanges;
    std::unique_ptr<FilterComparisonJob> m_comparison;
    // The window dragged last frame; the full scene's window behind the levels' (see reclassify()).
    bool m_windowDragged = false, m_fullWindowStale = false;
    std::vector<renderer::FilterMeasurement> m_measurements;
    bool m_measurementsStale = false;
    const std::vector<ui::DockPanel> m_panels;

    // --measure-interactive: the probe's edits and records; this UI frame started (after its wait) then.
    // SPLATLAB_READY_FILE (scripts that drive the window): created once the volume is shown, its gradients
    // computed and its first image on screen, when no progress modal holds the input any more; it then
    // holds how many finished images (a request's last) the view has shown, so that a script waits for
    // the image its input asked for rather than a fixed time.
    bool m_readyNoted = false;
    uint64_t m_finishedImages = 0, m_finishedImagesNoted = 0;
    void noteReady();
    std::optional<InteractiveProbe> m_probe;
    InteractiveProbe::Clock::time_point m_frameStart;
    void editForProbe();

    // Scripted runs show the 3D mouse's status but never move with it: their frames stay reproducible.
    std::optional<ui::SpaceMouse> m_spaceMouse;
    double m_lastPoll = 0, m_lastSpin = 0, m_lastTourStep = 0; // glfwGetTime() seconds
    bool m_knobMoved = false; // the 3D mouse moved the camera this frame (it ends a regime tour)
    double m_pollTime = 0;                 // this frame's events were read at this glfwGetTime()
};

template <class Step> bool EditorLoop::guarded(Step&& step) {
    try {
        step();
        return true;
    } catch (const renderer::LoadError& e) {
        report(e);
    } catch (const renderer::GlError& e) {
        report(e);
    } catch (const renderer::RenderError& e) {
        report(e);
    } catch (const std::bad_alloc&) { // what the step did not name itself
        report(std::runtime_error(renderer::volumeSubject(m_doc.scene.name) +
                                  ": out of memory in the editor; what it showed is kept"));
    }
    return false;
}
