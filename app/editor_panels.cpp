// The ImGui frame: the docked panels with what each is shown, the modals, and what their edits ask of the
// next frame (a render, the preview, the probe). The panels themselves are in ui/.
#include "editor_loop.h"
#include "slab_frames.h"

#include "renderer/oracle/probe.h"

#include <imgui.h>

#include <cstdio>
#include <imgui_impl_opengl3.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

std::vector<ui::DockPanel> EditorLoop::makePanels() {
    return {
        {"Transfer function", "left",
         [this] {
             m_tfChanged = ui::drawTransferFunctionPanel(
                 m_state, {.histogram = m_doc.volume ? &m_doc.histogram : nullptr,
                           .window = shownWindow(),
                           .dataRange = m_doc.volume ? m_doc.volume->range : renderer::ValueRange{},
                           .percentile = m_doc.percentile,
                           .visible = m_hasScene ? renderer::visibleValueRange(m_doc.scene) : renderer::ValueRange{},
                           .gradients = {.maxMagnitude = m_state.gradientsReady ? m_doc.scene.gradientMax : 0.0,
                                         .histogram = &m_doc.gradientHistogram},
                           .histogram2d = &m_doc.histogram2d,
                           .histogram2dWindow = m_doc.scene.window,
                           .windowSettled = !m_volumeJob && !m_classifyJob && !m_fullWindowStale && !m_windowChanged,
                           .gallery = m_hasScene ? m_gallery.thumbnails() : std::vector<ui::GalleryThumbnail>{}});
             m_windowChanged =
                 ui::drawWindowSection(m_state, {.volume = m_doc.volume ? &*m_doc.volume : nullptr,
                                                 .histogram = &m_doc.histogram,
                                                 .percentile = m_doc.percentile,
                                                 .window = shownWindow()});
         }},
        {"Settings", "left", [this] { m_settingsChanges = ui::drawSettingsPanel(m_state); }},
        {"Viewport", "viewport", [this] { m_viewport = ui::drawViewportPanel(m_state, m_image.id(), viewportOverlay()); }},
        {"Stats", "bottom",
         [this] {
             // The figures of what the viewport shows: a level's, or the full frame's with its GPU times
             // as they arrive.
             const int level = m_shown && m_doc.preview ? m_shown->level : 0;
             ui::drawStatsPanel(
                 {.frame = level ? m_shown->stats : m_render->latestStats(),
                  .volume = m_doc.volume ? &*m_doc.volume : nullptr,
                  .visibleSplats =
                      (level ? m_doc.preview->levels[size_t(level - 1)].scene : m_doc.scene).visibleCount(),
                  .sceneBytes = m_shown ? m_shown->sceneBytes : 0,
                  .sceneVoxels = level ? m_doc.preview->levels[size_t(level - 1)].volume.voxelCount() : 0,
                  .workingBytes = m_shown ? m_shown->workingBytes : 0,
                  .glRenderer = m_glRenderer,
                  .levels = levelsText()});
         }},
        {"Performance", "bottom",
         [this] { ui::drawPerformancePanel(m_state, m_perfHistory, [this] { return perfContext(); }); }},
        {"Filters", "bottom",
         [this] {
             m_filtersShown = true;
             m_filtersChanges = ui::drawFiltersPanel(
                 m_state, {.plane = m_lastPlane && m_doc.volume ? &*m_lastPlane : nullptr,
                           .dims = m_doc.scene.dims,
                           .origin = m_doc.scene.origin,
                           .spacing = m_doc.scene.spacing,
                           .radius = m_doc.scene.radius,
                           .frame = m_render->latestStats(),
                           .patches = m_patchCounts,
                           .measurements = m_measurements,
                           .cropPx = renderer::kComparisonCropPx,
                           .measuring = m_comparison != nullptr,
                           .measurementsStale = m_measurementsStale,
                           .truthProgress = m_comparison ? m_comparison->truth.fraction.load() : 0.0,
                           .settingsToMeasure = m_comparison && m_comparison->truth.done
                                                    ? m_comparison->settingsToMeasure()
                                                    : 0,
                           .slabsInForce = slabsOfStillView(m_state.slabs, m_state.settings).has_value()});
         }},
        {"Help", "bottom", [] { ui::drawHelpPanel(); }},
    };
}

ui::ViewportOverlay EditorLoop::viewportOverlay() const {
    ui::ViewportOverlay overlay;
    overlay.panes = splitPanes();
    if (!overlay.panes.empty()) return overlay; // the heatmap belongs to the one image
    if (!m_state.showHeatmap || !m_shown || !m_shownHasHeatmap) return overlay;
    overlay.heatmapTexture = m_heatmap.id();
    if (m_doc.volume)
        overlay.legend = ui::heatmapLegend(m_doc.scene.spacing, m_doc.scene.radius, m_shown->plane, m_state.settings,
                                           m_state.camera.fovYDeg);
    return overlay;
}

std::string EditorLoop::levelsText() const {
    if (!m_shown || !m_doc.preview) return {};
    std::string text = "on screen: " + (m_shown->level ? "1/" + std::to_string(1 << m_shown->level) + " per axis"
                                                       : std::string("full")) +
                       "\nlevel  ms      RMSE vs full";
    char line[64];
    for (int k = 0; k <= int(m_doc.preview->levels.size()) && k < kMaxViewLevels; ++k) {
        const double ms = m_shown->levelMs[size_t(k)], rmse = m_shown->levelRmse[size_t(k)];
        if (ms <= 0.0) continue;
        const std::string name = k ? "1/" + std::to_string(1 << k) : std::string("full");
        if (k > 0 && rmse >= 0.0)
            std::snprintf(line, sizeof line, "\n%-5s %7.1f  %.4f", name.c_str(), ms, rmse);
        else
            std::snprintf(line, sizeof line, "\n%-5s %7.1f", name.c_str(), ms);
        text += line;
    }
    return text;
}

std::string EditorLoop::perfContext() const {
    if (!m_doc.volume || !m_lastPlane || !m_hasScene) return "no volume, " + m_glRenderer;
    return ui::renderContext(m_doc.volume->name, m_doc.volume->dims,
                             {m_lastPlane->width, m_lastPlane->height}, m_state.settings, m_render->latestStats(),
                             m_glRenderer);
}

void EditorLoop::drawPanels(int frame) {
    // 1. A fresh ImGui frame; the panels report this frame's edits afresh.
    m_state.openingVolume = m_volumeJob ? m_volumeJob->path : std::filesystem::path();
    ImGui_ImplOpenGL3_NewFrame();
    m_window.newImGuiFrame(); // input from the queue: one button or key change a frame
    ImGui::NewFrame();
    m_settingsChanges = {};
    m_tfChanged = m_windowChanged = m_filtersShown = false;
    m_filtersChanges = {};
    m_viewport.cameraChanged = m_viewport.frame = false;
    // 2. The layout with its panels: --tab's in front for the first frames, and a dropped file's panel.
    std::vector<std::string> tabsToFront = frame <= 2 ? m_options.tabs : std::vector<std::string>{};
    if (const auto dropped =
            m_window.takeDroppedFile()) // its panel opens it as its button would (and shows its errors)
        tabsToFront.push_back(ui::dropFile(m_state, *dropped));
    // The menu bar first: the dock space fills what it leaves of the window.
    if (ImGui::BeginMainMenuBar()) {
        if (ImGui::BeginMenu("View")) {
            ui::drawViewMenuItems(m_layout, m_panels);
            ImGui::EndMenu();
        }
        ImGui::EndMainMenuBar();
    }
    ui::drawDockSpace(m_layout, m_panels, tabsToFront);
    // 3. The confirmation of a save, then the modals: an error, a volume being read, gradients being
    // computed.
    ui::drawSaveNotice(m_state.saveNotice);
    ui::drawErrorModal(m_state);
    if (ui::drawProgressModal("Opening volume",
                              m_volumeJob ? "Reading " + m_volumeJob->path.filename().string() +
                                                (m_volumeJob->cancel ? " (cancelling)" : "")
                                          : std::string(),
                              m_volumeJob ? m_volumeJob->fraction.load() : 1.0, m_volumeJob != nullptr))
        m_volumeJob->cancel = true;
    // One modal at a time: the gradients of the volume shown go on under a volume being read.
    if (ui::drawProgressModal("Computing gradients",
                              "Gradients of " + (m_doc.volume ? m_doc.volume->name : std::string()) +
                                  " (central differences, all cores)",
                              m_gradientJob ? m_gradientJob->fraction.load() : 1.0,
                              m_gradientJob && !m_volumeJob))
        m_gradientJob->cancel = true;
    ImGui::Render();
}

void EditorLoop::probeHoveredVoxel() {
    // The voxel under the mouse, for the next frame's tooltip and TF marker: the last full render's
    // view, so not while a drag shows the preview or a window edit left the full scene behind.
    m_state.probe.reset();
    const std::optional<glm::dvec2> pointer = pointerInPane(); // a split view's panes show one view
    if (pointer && m_lastPlane && m_doc.volume && !m_fullWindowStale && !m_state.preview.shown)
        if (const auto hit = renderer::probePixel(m_doc.scene, m_state.settings, *m_lastPlane, *pointer))
            m_state.probe = ui::EditorState::ProbedVoxel{
                hit->voxel, m_doc.volume->at(hit->voxel.x, hit->voxel.y, hit->voxel.z)};
    m_state.footprint.reset();
    if (m_state.inspectFootprint && m_state.probe)
        m_state.footprint = renderer::inspectFootprint(m_doc.scene, *m_lastPlane, m_state.settings, m_state.probe->voxel);
}

void EditorLoop::noteEdits() {
    // 1. The voxel under the mouse.
    probeHoveredVoxel();
    // 2. Any edit of the view ends a measurement under way and dates the last one.
    m_tfPending |= m_tfChanged;
    const bool viewEdited = m_settingsChanges.any() || m_tfChanged || m_windowChanged ||
                            m_filtersChanges.settingsChanged || m_viewport.cameraChanged ||
                            m_settingsChanges.openVolume || m_settingsChanges.sessionOpened ||
                            m_settingsChanges.frame || m_viewport.frame;
    if (viewEdited) {
        m_comparison.reset();
        m_measurementsStale = true;
    }
    // 3. A drag or the wheel: when the last moving input was (a dragged window re-classifies in full once
    //    it settles).
    const bool mouseDown = ImGui::IsMouseDown(ImGuiMouseButton_Left);
    m_windowDragged = m_windowChanged && mouseDown;
    if (m_viewport.cameraChanged || ((m_tfChanged || m_windowChanged) && mouseDown))
        m_state.preview.lastInput = glfwGetTime();
    // 4. Render next frame after an edit or when the viewport changed size.
    m_renderPending |= viewEdited;
    if (m_viewport.widthPx != m_renderWidth || m_viewport.heightPx != m_renderHeight) {
        m_renderWidth = m_viewport.widthPx, m_renderHeight = m_viewport.heightPx;
        m_renderPending = true;
    }
}
