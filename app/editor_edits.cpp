// Turning last frame's edits into the renderer's scenes: volumes opened and read, sessions opened,
// transfer function and window edits, gradients ready. Rendering the view is editor_viewport.cpp's.
#include "editor_loop.h"

#include "renderer/oracle/demo_scenes.h"

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <system_error>

void EditorLoop::applyEdits() {
    // A failed step waits for the next edit instead of repeating (and re-opening the error modal) every
    // frame.
    // 1. A volume read on the worker: on screen, or its error shown.
    takeLoadedVolume();
    // 2. Settings' buttons: open a volume, save the image, a session opened.
    applySettingsActions();
    // 3. The TF edited: the scene's LUT (and the preview's).
    applyTransferFunction();
    // 4. The window edited: re-classified on the worker, the levels only while dragged; every voxel once it
    //    settles.
    applyWindow();
    // 5. Gradients computed on the worker: shading and surface splats.
    takeGradients();
}

void EditorLoop::openVolume(const std::filesystem::path& path,
                            const std::optional<renderer::RawOptions>& raw) {
    m_volumeJob = std::make_unique<VolumeJob>(path, raw, m_state.tf, m_state.window);
    if (m_scripted) m_volumeJob->thread.join();
}

void EditorLoop::openDemoScene(const std::string& name, bool withLook, bool withCamera) {
    guarded([&] {
        if (withLook) {
            m_state.tf = renderer::demoScene(name, 1).tf; // a TF does not depend on the image
            m_state.tfSelected = m_state.tfColourSelected = -1;
            m_state.window.mode = renderer::WindowMode::DataRange;
            // Unlit at density 1, as the hard cases and their ground truth (the Filters panel's Measure).
            m_state.settings.density = 1.0;
            m_state.settings.shading = renderer::SplatSettings::Shading::None;
            m_tfPending = m_windowChanged = true;
        }
        if (withCamera) m_sceneCameraPending = name;
        openVolume(renderer::demoScenePath(name));
    });
}

bool EditorLoop::showVolume(LoadedVolume loaded, const std::filesystem::path& path,
                            const renderer::TransferFunction& tf) {
    return guarded([&] {
        if (!loaded.preview && m_options.preview)
            std::fprintf(stderr,
                         "note: --preview: %s has %zu voxels, fewer than the %zu M that get a preview; it "
                         "renders in full\n",
                         path.string().c_str(), loaded.volume.voxelCount(), ui::PreviewSettings::kMinMegaVoxels);
        // 1. The new scenes to the renderers first: should they not fit (out of GPU memory), the
        //    error shows and the document, its jobs and the view stay the previous volume's.
        m_render->setScenesNow(std::move(loaded.sceneForRender), std::move(loaded.levelsForRender));
        // 2. The jobs reading the document going away stop, and the document becomes the new volume.
        m_gradientJob.reset();
        m_classifyJob.reset(), m_classifyNext.reset(), m_fullWindowStale = false;
        Document next;
        next.tf = tf;
        next.histogram = std::move(loaded.histogram);
        next.percentile = loaded.percentile;
        next.scene = std::move(loaded.scene);
        next.preview = std::move(loaded.preview); // levels built and classified on the worker
        next.volume = std::move(loaded.volume);
        m_hasScene = true;
        m_doc = std::move(next);
        ++m_sceneVersion;
        ++m_volumesShown;
        m_state.preview.available = m_doc.preview != nullptr;
        m_state.gradientsReady = false;
        m_state.loadedVolume = path;
        m_state.volumeFile = path.string();
        if (!renderer::demoSceneOfPath(path)) ui::noteRecentFile(m_state, ui::FileKind::Volume, path);
        m_window.setTitle(path);
        std::vector<const renderer::Volume*> levels;
        if (m_doc.preview)
            for (const Level& level : m_doc.preview->levels) levels.push_back(&level.volume);
        m_gradientJob = std::make_unique<GradientJob>(*m_doc.volume, levels);
        if (m_scripted) m_gradientJob->thread.join();
    });
}

void EditorLoop::reclassify(bool levelsOnly) {
    if (m_classifyJob) { // the last one asked starts when this one ends; a full one wins over levels only
        m_classifyNext = m_classifyNext ? (*m_classifyNext && levelsOnly) : levelsOnly;
        return;
    }
    m_fullWindowStale = levelsOnly && m_doc.preview;
    guarded([&] {
        m_classifyJob = std::make_unique<ClassifyJob>(m_doc, m_doc.tf, renderer::windowFor(*m_doc.volume, m_state.window),
                                                      levelsOnly && m_doc.preview);
    });
    if (m_scripted && m_classifyJob) { // deterministic frames: this frame shows it
        m_classifyJob->thread.join();
        takeClassified();
    }
}

void EditorLoop::classifyNow() {
    const auto finish = [&] {
        while (m_classifyJob) { // takeClassified may start the one asked meanwhile
            if (m_classifyJob->thread.joinable()) m_classifyJob->thread.join();
            takeClassified();
        }
    };
    finish();
    if (m_fullWindowStale) reclassify(false);
    finish();
}

void EditorLoop::takeClassified() {
    if (!m_classifyJob || !m_classifyJob->done) return;
    if (m_classifyJob->thread.joinable()) m_classifyJob->thread.join();
    std::optional<Classified> done = std::move(m_classifyJob->result);
    if (!m_classifyJob->error.empty()) report(std::runtime_error(m_classifyJob->error));
    m_classifyJob.reset();
    if (done) {
        // Classified with the TF at its start: the TF as it is now, in the scenes and after them on the GPU.
        if (!done->levelsOnly) {
            m_doc.scene = std::move(done->full);
            renderer::setTransferFunction(m_doc.scene, m_doc.tf);
            ++m_sceneVersion; // a split view's ground truth is of another scene now
            m_doc.histogram2d = renderer::valueGradientHistogram(m_doc.scene);   // over the new window
        }
        if (m_doc.preview)
            for (size_t k = 0; k < m_doc.preview->levels.size() && k < done->levels.size(); ++k) {
                m_doc.preview->levels[k].scene = std::move(done->levels[k]);
                renderer::setTransferFunction(m_doc.preview->levels[k].scene, m_doc.tf);
            }
        if (done->levelsOnly)
            m_render->setLevelScenes(std::move(done->levelsForRender));
        else
            m_render->setScenes(std::move(done->fullForRender), std::move(done->levelsForRender));
        m_render->setLuts(renderer::tfTables(m_doc.scene), levelTables(m_doc));
        m_renderPending = true;
    }
    if (m_classifyNext) {
        const bool levelsOnly = *m_classifyNext;
        m_classifyNext.reset();
        reclassify(levelsOnly);
    }
}

renderer::ValueRange EditorLoop::shownWindow() const {
    return m_fullWindowStale && m_doc.preview ? m_doc.preview->levels[0].scene.window : m_doc.scene.window;
}

void EditorLoop::takeLoadedVolume() {
    if (!m_volumeJob || !m_volumeJob->done) return;
    if (m_volumeJob->thread.joinable()) m_volumeJob->thread.join();
    const std::unique_ptr<VolumeJob> job = std::move(m_volumeJob);
    if (!job->error.empty())
        report(std::runtime_error(job->error));
    else if (job->result && showVolume(std::move(*job->result), job->path, job->tf))
        m_renderPending = true;
}

void EditorLoop::applySettingsActions() {
    if (!m_settingsChanges.openScene.empty()) {
        openDemoScene(m_settingsChanges.openScene, true, true);
        m_renderPending = true;
    }
    if (m_settingsChanges.openVolume) {
        openVolume(m_state.volumeFile);
        m_renderPending = true;
    }
    if (m_settingsChanges.saveImage) startSaveView(m_state.imageFile);
    finishSaveView(m_scripted); // written once the render thread has drawn it
    if (m_settingsChanges.sessionOpened) {
        // Another volume: load it with the session's window and TF; the same one: re-classify it.
        const std::filesystem::path& v = m_settingsChanges.sessionVolume;
        std::error_code ec;
        if (!v.empty() && !std::filesystem::equivalent(v, m_state.loadedVolume, ec))
            openVolume(v);
        else
            m_tfPending = m_windowChanged = true;
        m_renderPending = true;
    }
}

void EditorLoop::applyTransferFunction() {
    if (!m_hasScene || !m_tfPending) return;
    m_tfPending = false;
    guarded([&] {
        m_doc.tf = m_state.tf;
        renderer::setTransferFunction(m_doc.scene, m_doc.tf);
        ++m_sceneVersion;
        if (m_doc.preview) m_doc.preview->setTransferFunction(m_doc.tf);
        // The lists stay; only the LUTs travel.
        m_render->setLuts(renderer::tfTables(m_doc.scene), levelTables(m_doc));
    });
}

void EditorLoop::applyWindow() {
    takeClassified();
    if (m_hasScene && m_windowChanged) {
        m_windowChanged = false;
        // While dragged, the levels' voxels only (a finest level is an eighth of them); all once it settles.
        reclassify(m_windowDragged && m_doc.preview && m_state.preview.whileMoving);
    }
    if (m_fullWindowStale && !m_classifyJob && !(m_state.preview.whileMoving && m_state.preview.moving(m_pollTime)))
        reclassify(false); // every voxel once the drag settles (or the preview is turned off)
}

void EditorLoop::takeGradients() {
    // Not while a classification reads the gradients it would replace: they come in after it.
    if (!m_gradientJob || !m_gradientJob->done || m_classifyJob) return;
    if (m_gradientJob->thread.joinable()) m_gradientJob->thread.join();
    std::optional<Gradients> computed = std::move(m_gradientJob->result);
    if (!m_gradientJob->error.empty()) m_state.errorMessage = "gradients: " + m_gradientJob->error;
    m_gradientJob.reset();
    if (!m_hasScene || !computed) return;
    // Shading and surface splats become available: the packed gradients into the scenes (computed and
    // packed on the worker), and to the render thread, where only they travel to the GPU.
    guarded([&] {
        m_doc.gradients = std::move(computed->field);
        m_doc.gradientHistogram = std::move(computed->magnitudeCounts);
        renderer::addGradients(m_doc.scene, std::move(computed->packed));   // re-bakes the TF with them
        ++m_sceneVersion;
        m_doc.histogram2d = renderer::valueGradientHistogram(m_doc.scene);
        if (m_doc.preview)
            for (size_t k = 0; k < m_doc.preview->levels.size() && k < computed->levelFields.size(); ++k) {
                Level& level = m_doc.preview->levels[k];
                level.gradients = std::move(computed->levelFields[k]);
                renderer::addGradients(level.scene, std::move(computed->levelPacked[k]));
            }
        m_render->setGradients(computed->forRender, computed->levelsForRender);
        // A TF's gradient opacity applies from now on: its factors follow the gradients.
        m_render->setLuts(renderer::tfTables(m_doc.scene), levelTables(m_doc));
        m_state.gradientsReady = true;
    });
    m_renderPending = true;
}
