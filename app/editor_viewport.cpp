// The viewport's render step: framing, the Performance panel's spin, the full render or the preview,
// saving the view, and the Filters panel's figures (patch counts, the filter measurement).
#include "editor_loop.h"

#include "renderer/io/image.h"

#include <algorithm>

void EditorLoop::renderViewport() {
    // 1. Frame the scene when asked (needs the viewport's aspect and the scene's current LUT).
    frameIfAsked();
    // 2. Continuous rendering (Performance panel): every frame renders, turning the camera if asked.
    spinIfContinuous();
    // 3. The view: the preview while it moves, the full render once it settles.
    renderIfPending();
    // 4. The Filters panel's patches per filter, of the view just rendered.
    countPatchesIfShown();
}

void EditorLoop::stepFilterMeasurement() {
    if (m_filtersChanges.cancel) m_comparison.reset();
    if (m_filtersChanges.measure && m_splats && m_lastPlane && !m_comparison) {
        m_measurements.clear();
        m_measurementsStale = false;
        m_comparison = std::make_unique<FilterComparisonJob>(m_doc.scene, *m_lastPlane, m_state.settings);
    }
    if (m_comparison && m_comparison->truth.done) {
        if (m_comparison->truth.thread.joinable()) m_comparison->truth.thread.join();
        if (!m_comparison->truth.error.empty()) {
            m_state.errorMessage = "measuring the filters: " + m_comparison->truth.error;
            m_comparison.reset();
        } else if (m_comparison->measured < FilterComparisonJob::kFilters.size()) {
            guarded([&] {
                m_measurements.push_back(renderer::measureFilter(
                    *m_splats, m_comparison->view, m_comparison->crop, *m_comparison->truth.result,
                    m_comparison->settings, FilterComparisonJob::kFilters[m_comparison->measured++], 3));
            });
            m_renderPending = true; // re-rendered below: the crop replaced the view's targets
        } else {
            m_comparison.reset();
        }
    }
}

void EditorLoop::frameIfAsked() {
    // Framing needs the viewport's aspect, known from the first frame on, and the scene's current LUT.
    // No volume, none being read: nothing to frame. One being read: framed once it is shown.
    m_framePending =
        (m_framePending || m_settingsChanges.frame || m_viewport.frame) && (m_splats || m_volumeJob);
    if (m_framePending && m_renderWidth > 0 && !m_volumeJob) {
        m_framePending = false;
        m_state.camera = renderer::framedCamera(m_state.camera, m_doc.scene, m_state.settings, m_renderWidth,
                                                m_renderHeight, ui::kMinDistance, ui::kMaxDistance);
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

void EditorLoop::renderIfPending() {
    // While the view moves, the preview; once it settles, the full render.
    const bool preview = m_doc.preview && m_state.preview.whileMoving &&
                         (m_options.preview || m_state.preview.moving(m_pollTime));
    m_renderPending |= m_state.preview.shown && !preview;
    const bool renderNow = m_splats && m_renderPending && m_renderWidth > 0;
    if (renderNow) {
        m_renderPending = false;
        const auto start = std::chrono::steady_clock::now();
        const double intervalMs =
            m_renderedLastFrame && m_lastRenderStart
                ? std::chrono::duration<double, std::milli>(start - *m_lastRenderStart).count()
                : 0.0;
        m_lastRenderStart = start;
        if (!renderView(preview))
            m_texture = 0;
        else if (!preview)
            m_perfHistory.addRender(m_splats->stats(),
                                    intervalMs); // the Performance panel's figures are of full renders
    }
    m_renderedLastFrame = renderNow;
}

void EditorLoop::countPatchesIfShown() {
    if (!m_splats || !m_lastPlane || !m_filtersShown || !m_patchCountsStale) return;
    m_patchCountsStale = false;
    guarded([&] {
        renderer::SplatSettings adaptive = m_state.settings;
        adaptive.filter = renderer::FilterMode::Adaptive;
        std::array<uint64_t, 3> counts{};
        for (uint8_t mode : m_splats->patchModes(*m_lastPlane, adaptive))
            ++counts[std::min<size_t>(mode, 2)];
        m_patchCounts = counts;
    });
}

bool EditorLoop::renderView(bool preview) {
    return guarded([&] {
        const renderer::ImagePlane plane =
            renderer::makeImagePlane(m_state.camera, m_doc.scene.centre, m_doc.scene.radius, m_renderWidth,
                                     m_renderHeight, m_doc.scene.axes);
        // Shading waits for the gradients (computed after a volume loads); until then, unshaded.
        renderer::SplatSettings drawn = m_state.settings;
        if (!m_state.gradientsReady)
            drawn.shading = renderer::SplatSettings::Shading::None, drawn.surfaceFlatten = 1.0;
        m_state.preview.shown = preview;
        if (preview) { // the same extinction per unit length from voxels twice the size
            drawn.density = renderer::densityFor(m_doc.preview->volume, *m_doc.volume, drawn.density);
            m_doc.preview->splats.render(plane, drawn);
            m_texture = m_doc.preview->splats.displayTexture(m_state.background.data(), m_state.showHeatmap);
            return;
        }
        m_splats->render(plane, drawn);
        m_texture = m_splats->displayTexture(m_state.background.data(), m_state.showHeatmap);
        m_lastPlane = plane;
        m_patchCountsStale = true;
    });
}

std::optional<std::string> EditorLoop::saveView(const std::filesystem::path& path) {
    std::optional<std::string> written;
    guarded([&] {
        if (!m_splats || m_texture == 0)
            throw renderer::LoadError(path.string(), "", "no view to save: open a volume first");
        const bool behind = m_fullWindowStale || m_state.preview.shown; // the full renderer lacks this view
        if (m_fullWindowStale) reclassify();
        if (behind && !renderView(false)) return;
        const renderer::Image image =
            m_state.showHeatmap ? m_splats->readbackHeatmap() : m_splats->readback();
        renderer::writeImage(image, path, m_state.background.data());
        written = std::to_string(image.width) + " x " + std::to_string(image.height) +
                  (m_state.showHeatmap ? " (heatmap)" : "");
        m_state.imageSaved = "wrote " + path.filename().string() + ", " + *written;
    });
    return written;
}
