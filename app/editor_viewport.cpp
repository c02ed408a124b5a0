// The viewport's render step: framing, the Performance panel's spin, the view asked of the render thread
// and its images shown, saving the view, and the Filters panel's figures (patch counts, the filter
// measurement).
#include "editor_loop.h"

#include "heatmap_blend.h"
#include "slab_frames.h"
#include "renderer/io/image.h"
#include "renderer/model/detail_levels.h"
#include "renderer/oracle/demo_scenes.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>

void EditorLoop::renderViewport() {
    // 1. Frame the scene when asked (needs the viewport's aspect and the scene's current LUT).
    frameIfAsked();
    // 2. Continuous rendering (Performance panel): every frame renders, turning the camera if asked; the
    //    regime tour (Filters panel) moves the camera too.
    spinIfContinuous();
    tourIfRunning();
    // 3. The view asked of the render thread (after --measure-interactive's edit); the newest image it
    //    finished, on screen.
    editForProbe();
    renderIfPending();
    showRenderedView();
    noteSlabStatus();
    stepSplitTruth(); // |A - ground truth|: its truth, and the difference of the image shown
    // 4. The Filters panel's patches per filter, of the full frame shown.
    countPatchesIfShown();
    // 5. The TF panel's Gallery, after the view: one preset's thumbnail at a time.
    drawGalleryIfOpen();
}

int EditorLoop::thumbnailLevel() const {
    // A large scan's thumbnails come from the finest level small enough (a 96-pixel image needs no more).
    if (m_doc.volume->voxelCount() <= kThumbnailMaxVoxels || !m_doc.preview) return 0;
    const auto& levels = m_doc.preview->levels;
    for (size_t k = 0; k < levels.size(); ++k)
        if (levels[k].volume.voxelCount() <= kThumbnailMaxVoxels || k + 1 == levels.size()) return int(k) + 1;
    return 0;
}

const renderer::SplatScene& EditorLoop::thumbnailScene(int level) const {
    return level ? m_doc.preview->levels[size_t(level - 1)].scene : m_doc.scene;
}

ThumbnailSource EditorLoop::thumbnailSource(int level) const {
    const renderer::SplatScene& scene = thumbnailScene(level);
    ThumbnailSource source;
    source.plane = thumbnailPlane(m_doc.scene, m_state.camera.up);
    source.settings = m_state.settings;
    source.settings.heatmap = false;
    if (!m_state.gradientsReady) { // as the view: unshaded until the gradients are computed
        source.settings.shading = renderer::SplatSettings::Shading::None;
        source.settings.surfaceFlatten = 1.0;
    }
    source.level = level;
    source.window = scene.window;
    source.shownTables = renderer::tfTables(scene);
    if (level)
        source.settings.density = renderer::densityFor(m_doc.preview->levels[size_t(level - 1)].volume,
                                                       *m_doc.volume, m_state.settings.density);
    return source;
}

void EditorLoop::drawGalleryIfOpen() {
    // Not while the scene is being re-classified; and once every thumbnail of this view is drawn, each
    // frame costs only the check of what they were drawn from.
    if (!m_state.tfGalleryOpen || !m_hasScene || !m_doc.volume || m_classifyJob || m_fullWindowStale) return;
    const int level = thumbnailLevel();
    const renderer::ValueRange& window = thumbnailScene(level).window;
    const auto of = std::tuple{m_volumesShown, window.lo, window.hi, m_state.gradientsReady};
    if (m_galleryOf != of) m_gallery.invalidate(), m_galleryOf = of;
    if (m_gallery.complete()) return;
    const ThumbnailSource source = thumbnailSource(level);
    guarded([&] { m_gallery.step(*m_render, source, m_state.background, m_scripted); });
}

void EditorLoop::stepFilterMeasurement() {
    if (m_filtersChanges.cancel) m_comparison.reset(), m_measurement.reset();
    if (m_filtersChanges.measure && m_hasScene && m_lastPlane && !m_comparison) {
        m_measurements.clear();
        m_measurementsStale = false;
        m_comparison = std::make_unique<FilterComparisonJob>(m_doc.scene, *m_lastPlane, m_state.settings,
                                                             slabsOfStillView(m_state.slabs, m_state.settings));
    }
    if (!m_comparison) return m_measurement.reset();
    if (!m_comparison->truth.done) return;
    if (m_comparison->truth.thread.joinable()) m_comparison->truth.thread.join();
    if (!m_comparison->truth.error.empty()) {
        m_state.errorMessage = "measuring the filters: " + m_comparison->truth.error;
        m_comparison.reset();
        return;
    }
    // One setting at a time on the render thread (timed on the whole view, compared on the crop).
    if (m_measurement) {
        if (!m_scripted && m_measurement->wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
        guarded([&] { m_measurements.push_back(m_measurement->get()); });
        m_measurement.reset();
        m_renderPending = true; // the crop replaced the view's targets: the view again
    }
    FilterComparisonJob& job = *m_comparison;
    if (job.measured == job.settingsToMeasure()) return m_comparison.reset();
    if (job.measured == job.toMeasure.size()) { // the slabs in force, on the render thread's slab pass
        ++job.measured;
        m_measurement = m_render->run([view = job.view, crop = job.crop, truth = job.truth.result->ofSlabs(*job.slabs),
                                       settings = job.settings, slabs = *job.slabs, ended = job.ended,
                                       repeats = m_state.measureRepeats](Renderers& r) {
            const auto draw = [&](const renderer::ImagePlane& p) {
                return r.slabs.render(p, settings, slabs, [&] { return ended->load(); });
            };
            return renderer::measureSlabs(draw, view, crop, truth, settings, slabs, repeats);
        });
        return;
    }
    const renderer::SplatSettings& settings = job.toMeasure[job.measured++];
    m_measurement = m_render->run([view = job.view, crop = job.crop, truth = job.truth.result->of(settings), settings,
                                   repeats = m_state.measureRepeats](Renderers& r) {
        return renderer::measureSetting(*r.full, view, crop, truth, settings, repeats);
    });
}

void EditorLoop::frameIfAsked() {
    // Framing needs the viewport's aspect, known from the first frame on, and the scene's current LUT.
    // No volume, none being read: nothing to frame. One being read: framed once it is shown.
    m_framePending =
        (m_framePending || m_settingsChanges.frame || m_viewport.frame) && (m_hasScene || m_volumeJob);
    if (m_framePending && m_renderWidth > 0 && !m_volumeJob) {
        m_framePending = false;
        m_state.camera = renderer::framedCamera(m_state.camera, m_doc.scene, m_state.settings, m_renderWidth,
                                                m_renderHeight, ui::kMinDistance, ui::kMaxDistance);
        m_renderPending = true;
    }
    if (m_sceneCameraPending && m_renderHeight > 0 && !m_volumeJob) {
        // Framed for the height of the image it is drawn in: a pane's in a split view.
        const int height = m_state.split.enabled
                               ? ui::splitLayout(m_renderWidth, m_renderHeight, m_state.split.shownImagePanes(),
                                                 m_state.split.difference != ui::SplitDifference::Off)
                                     .panes.front()
                                     .height
                               : m_renderHeight;
        guarded([&] { m_state.camera = renderer::demoScene(*m_sceneCameraPending, height).camera; });
        m_sceneCameraPending.reset();
        m_renderPending = true;
    }
}

void EditorLoop::spinIfContinuous() {
    // Scripted runs turn by a fixed 1/60 s a frame, so their pictures stay reproducible.
    const bool continuous = m_state.perf.renderContinuously && m_state.errorMessage.empty();
    if (continuous && m_state.perf.spinDegPerS != 0.0) {
        const double dt = m_scripted ? 1.0 / 60.0 : std::min(m_pollTime - m_lastSpin, 0.1);
        ui::applyOrbitInput(m_state.camera,
                            {.rotateDxPx = float(-m_state.perf.spinDegPerS * dt / ui::kOrbitDegPerPx)});
        m_comparison.reset(); // a turning view has no measurement to take
        m_measurementsStale = true;
    }
    m_lastSpin = m_pollTime;
    m_renderPending |= continuous;
}

void EditorLoop::tourIfRunning() {
    // Last frame's camera input of the user's ends the tour; scripted runs step 1/60 s a frame. A UI frame
    // slower than 0.25 s (a loaded llvmpipe) slows the tour rather than jumping through the regimes.
    const bool userMoved = m_viewport.cameraChanged || m_viewport.frame || m_settingsChanges.cameraChanged ||
                           m_settingsChanges.frame || m_knobMoved;
    const double dt = m_scripted ? 1.0 / 60.0 : std::min(m_pollTime - m_lastTourStep, 0.25);
    m_lastTourStep = m_pollTime;
    if (ui::stepRegimeTour(m_state, dt, userMoved)) {
        m_renderPending = true;
        m_comparison.reset(); // a moving view has no measurement to take
        m_measurementsStale = true;
    }
}

ViewRequest EditorLoop::viewRequest() const {
    ViewRequest request;
    request.plane = renderer::makeImagePlane(m_state.camera, m_doc.scene.centre, m_doc.scene.radius,
                                             m_renderWidth, m_renderHeight, m_doc.scene.axes);
    // Shading waits for the gradients (computed after a volume loads); until then, unshaded.
    request.full = m_state.settings;
    if (!m_state.gradientsReady)
        request.full.shading = renderer::SplatSettings::Shading::None, request.full.surfaceFlatten = 1.0;
    if (m_doc.preview) // the same extinction per unit length from voxels 2, 4, 8 times the size
        for (const Level& level : m_doc.preview->levels) {
            request.coarse.push_back(request.full);
            request.coarse.back().density = renderer::densityFor(level.volume, *m_doc.volume, request.full.density);
        }
    request.background = m_state.background;
    request.heatmap = m_state.showHeatmap;
    // Scripted runs draw exactly one image a frame: --preview's level (1/2 per axis), or the full frame.
    using Levels = ViewRequest::Levels;
    request.levels = m_options.preview                               ? Levels::FinestOnly
                     : m_scripted || !m_state.preview.whileMoving ? Levels::FullOnly
                                                                      : Levels::Progressive;
    // While the window is dragged only the levels are re-classified: the finest shows the new window.
    if (m_fullWindowStale && m_doc.preview) request.levels = Levels::FinestOnly;
    request.budgetMs = m_state.preview.budgetMs > 0.0 ? m_state.preview.budgetMs : m_state.preview.defaultBudgetMs;
    splitViewRequest(request); // a split view: its panes' settings, at a pane's size
    request.slabs = slabsOfView();
    return request;
}

std::optional<renderer::SlabOptions> EditorLoop::slabsOfView() const {
    // Not where no frame rests: a preview, a window still dragged, continuous rendering, a split view (the
    // Settings panel greys the section out for it, slab_section.cpp).
    if (m_options.preview || m_fullWindowStale || m_state.perf.renderContinuously || m_state.split.enabled)
        return std::nullopt;
    return slabsOfStillView(m_state.slabs, m_state.settings);
}

int EditorLoop::farViewLevel(const ViewRequest& request) {
    if (!m_state.preview.farLevels || !m_doc.preview || m_doc.preview->levels.empty()) return 0;
    // A zoom that wobbles about a threshold keeps its level: 10 % each way.
    constexpr double kHysteresis = 0.1;
    const renderer::SplatScene& full = m_doc.scene;
    int level = renderer::coarsestLowPassLevel(full.dims, full.origin, full.spacing, request.plane, request.full,
                                               int(m_doc.preview->levels.size()), m_farLevel, kHysteresis);
    if (level == 0) return 0;
    // The optical mass test, once a scene version. One fine value a coarse voxel (Downsample::PickOne) keeps
    // the mass in expectation; the test still refuses a level that lost a feature. Counted by class, so
    // not for a TF with gradient opacity or a 2D TF (a pass over every voxel on the UI thread).
    if (m_levelMassOf != m_sceneVersion) {
        m_levelMassChange.clear();
        if (full.tf2d.empty() && full.gradientFactors.empty())
            for (const Level& l : m_doc.preview->levels)
                m_levelMassChange.push_back(renderer::opticalMassChange(full, l.scene));
        m_levelMassOf = m_sceneVersion;
    }
    while (level > 0 && size_t(level) <= m_levelMassChange.size() &&
           m_levelMassChange[size_t(level - 1)] > renderer::kMaxMassChange)
        --level;
    return level;
}

void EditorLoop::renderIfPending() {
    if (!m_hasScene || !m_renderPending || m_renderWidth <= 0) return;
    // Continuous rendering asks for the next frame once the last finished: back to back, none superseded.
    if (m_state.perf.renderContinuously && !m_scripted && m_render->busy()) return;
    m_renderPending = false;
    ViewRequest request = viewRequest();
    request.finestLevel = m_farLevel = farViewLevel(request);
    m_slabsAsked = request.slabs.has_value();
    m_viewRequest = m_render->requestView(std::move(request));
    if (m_probe) m_probe->requested(m_viewRequest);
    if (m_scripted) { // deterministic frames: this frame shows this request's image
        m_render->waitForView(m_viewRequest);
        takeRenderErrors();
    }
}

void EditorLoop::showRenderedView() {
    std::optional<RenderedView> view = m_render->takeView();
    if (!view) return;
    m_image.upload(view->width, view->height, view->rgba);
    m_shownHasHeatmap = !view->heatmapRgba.empty();
    if (m_shownHasHeatmap) m_heatmap.upload(view->width, view->height, view->heatmapRgba);
    showSplitPanes(*view);
    view->rgba = {}, view->heatmapRgba = {};
    if (m_probe) m_probe->imageShown(view->request, view->level, view->finestLevel, InteractiveProbe::Clock::now());
    m_finishedImages += view->last;
    m_state.preview.shown = view->level > view->finestLevel;
    m_state.preview.shownLevel = view->level;
    m_state.preview.farLevel = view->finestLevel;
    if (view->slabs) {
        char text[96];
        std::snprintf(text, sizeof text, "slabs shown: %.1f s at %dx%d", view->slabMs / 1000.0, view->width,
                      view->height);
        m_state.slabs.status = text;
    } else if (view->level == view->finestLevel) { // the Performance and Filters panels' figures are of the
                                                   // view's finished frames (full, or a far view's level)
        const auto now = std::chrono::steady_clock::now();
        const double intervalMs = m_state.perf.renderContinuously && m_lastFullFrame
                                      ? std::chrono::duration<double, std::milli>(now - *m_lastFullFrame).count()
                                      : 0.0;
        m_lastFullFrame = now;
        m_perfHistory.addRender(view->stats, intervalMs);
        m_lastPlane = view->plane;
        m_patchCountsStale = true;
    }
    m_shown = std::move(view);
}

void EditorLoop::noteSlabStatus() {
    ui::SlabView& slabs = m_state.slabs;
    if (!m_slabsAsked) return slabs.status.clear();
    if (m_shown && m_shown->slabs && m_shown->request == m_viewRequest) return; // "slabs shown: ..."
    if (m_render->busy()) {
        slabs.status = "drawing slabs after the sheets' frame";
    } else {
        const std::string note = m_render->slabNote();
        slabs.status = note.empty() ? std::string() : "sheets shown: " + note;
    }
}

void EditorLoop::countPatchesIfShown() {
    if (m_patchModes &&
        (m_scripted || m_patchModes->wait_for(std::chrono::seconds(0)) == std::future_status::ready)) {
        guarded([&] {
            std::array<uint64_t, 3> counts{};
            for (uint8_t mode : m_patchModes->get()) ++counts[std::min<size_t>(mode, 2)];
            m_patchCounts = counts;
        });
        m_patchModes.reset();
    }
    if (!m_hasScene || !m_lastPlane || !m_filtersShown || !m_patchCountsStale || m_patchModes) return;
    m_patchCountsStale = false;
    renderer::SplatSettings adaptive = m_state.settings;
    adaptive.filter = renderer::FilterMode::Adaptive;
    m_patchModes = m_render->run([plane = *m_lastPlane, adaptive](Renderers& r) {
        return r.full->patchModes(plane, adaptive);
    });
}

void EditorLoop::startSaveView(const std::filesystem::path& path) {
    guarded([&] {
        if (!m_hasScene || m_image.id() == 0)
            throw renderer::LoadError(path.string(), "", "no view to save: open a volume first");
        classifyNow(); // the full scene, with the window on screen
        ViewRequest view = viewRequest();
        const double opacity = view.heatmap ? std::clamp(m_state.heatmapOpacity, 0.0, 1.0) : 0.0;
        if (!view.others.empty()) {
            m_save = PendingSave{
                .path = path, .heatmapOpacity = 0.0, .images = {}, .split = startSaveSplitView(view), .slabs = false};
            return;
        }
        // As the view ends: in slabs where it does (a setting they refuse is said, not saved as sheets).
        m_save = PendingSave{
            path, opacity,
            m_render->run([plane = view.plane, settings = view.full, slabs = view.slabs, opacity](Renderers& r) {
                r.full->render(plane, settings);
                renderer::Image image = opacity >= 1.0 ? renderer::Image()
                                        : slabs        ? r.slabs.render(plane, settings, *slabs)
                                                       : r.full->readback();
                return std::pair{std::move(image), opacity > 0.0 ? r.full->readbackHeatmap() : renderer::Image()};
            }),
            {}, view.slabs.has_value()};
    });
}

std::optional<std::string> EditorLoop::finishSaveView(bool wait) {
    if (!m_save) return std::nullopt;
    const auto ready = [](const auto& f) { return f.wait_for(std::chrono::seconds(0)) == std::future_status::ready; };
    if (!wait && !(m_save->split.valid() ? ready(m_save->split) : ready(m_save->images))) return std::nullopt;
    PendingSave save = std::move(*m_save);
    m_save.reset();
    std::optional<std::string> written;
    if (save.split.valid()) {
        guarded([&] {
            const SplitImage split = save.split.get();
            renderer::writeImage(split.panes, save.path, m_state.background.data());
            written = std::to_string(split.panes.width) + " x " + std::to_string(split.panes.height) +
                      splitSavedText(split);
            m_state.imageSaved = "wrote " + save.path.filename().string() + ", " + *written;
        });
        return written;
    }
    guarded([&] {
        auto [image, heatmap] = save.images.get();
        const renderer::Image shown = blendHeatmap(std::move(image), std::move(heatmap), save.heatmapOpacity);
        renderer::writeImage(shown, save.path, m_state.background.data());
        char what[48] = "";
        if (save.heatmapOpacity >= 1.0) std::snprintf(what, sizeof what, " (heatmap)");
        else if (save.heatmapOpacity > 0.0) std::snprintf(what, sizeof what, " (heatmap at %.2f)", save.heatmapOpacity);
        written = std::to_string(shown.width) + " x " + std::to_string(shown.height) + what +
                  (save.slabs && save.heatmapOpacity < 1.0 ? " (image-aligned slabs)" : "");
        m_state.imageSaved = "wrote " + save.path.filename().string() + ", " + *written;
        m_state.saveNotice = ui::savedNotice(save.path, *written);
        ui::noteRecentFile(m_state, ui::FileKind::Image, save.path);
    });
    return written;
}
