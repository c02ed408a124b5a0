// The editor's frame loop around the edits and the view: starting from the flags or a session, reading
// input, and showing the drawn frame (with a scripted run's outputs). Each step is a method of EditorLoop.
#include "editor_loop.h"

#include "renderer/io/atomic_file.h"

#include "renderer/gl/driver_profile.h"
#include "renderer/gl/gl_context.h"
#include "renderer/io/image.h"
#include "ui/session.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

EditorLoop::EditorLoop(const EditorOptions& options, EditorWindow& window)
    : m_options(options), m_window(window), m_scripted(options.frames > 0),
      m_render(std::make_unique<RenderThread>()), m_framePending(options.fit), m_panels(makePanels()) {
    m_glRenderer = m_render->glRenderer();
    m_state.preview.defaultBudgetMs = m_render->defaultBudgetMs();
    m_render->setOnImage([] { glfwPostEmptyEvent(); }); // wakes waitForInput to show it
    if (options.measureEdits > 0) m_probe.emplace(options.measureEdits);
}

bool EditorLoop::start() {
    std::filesystem::path volumePath = m_options.volumePath;
    // The recent files of earlier runs; a damaged list is reported and replaced, never fatal.
    m_state.configDir = ui::configFolder();
    if (!m_state.configDir.empty()) {
        try {
            m_state.recentFiles = ui::loadRecentFiles(m_state.configDir);
        } catch (const renderer::LoadError& e) {
            std::fprintf(stderr, "splatlab editor: %s (starting with no recent files)\n", e.what());
        }
        try {
            ui::loadDockLayout(m_layout, m_state.configDir);
        } catch (const renderer::LoadError& e) {
            std::fprintf(stderr, "splatlab editor: %s (starting with the default layout)\n", e.what());
        }
    }
    guarded([&] {
        m_state.camera = m_options.camera;
        m_state.camera.up = renderer::axisFromName(m_options.upAxis);
        m_state.settings = m_options.settings;
        if (m_options.cullingByDriver)
            m_state.settings.occlusionCulling = renderer::driverProfile(m_glRenderer).occlusionCulling;
        m_state.showHeatmap = m_options.settings.heatmap;
        m_state.heatmapOpacity = m_options.heatmapOpacity;
        if (!m_options.split.empty()) { // 2 or 4 filters (main.cpp refuses other counts)
            m_state.split.enabled = true;
            m_state.split.imagePanes = int(m_options.split.size());
            for (size_t i = 0; i < m_options.split.size() && i < m_state.split.panes.size(); ++i)
                m_state.split.panes[i] = ui::SplitPane{m_options.split[i], m_options.settings.compositing};
            m_state.split.difference = m_options.splitDifference;
        }
        m_state.window = m_options.window;
        m_state.perf.renderContinuously = m_options.continuous || m_options.spinDegPerS != 0.0;
        if (!(std::abs(m_options.spinDegPerS) <= 90.0))
            throw renderer::RenderError("--spin takes -90 to 90 degrees a second, got " +
                                        std::to_string(m_options.spinDegPerS));
        m_state.perf.spinDegPerS = m_options.spinDegPerS;
        std::vector<std::string> notes;
        m_state.tf = renderer::transferFunctionFromSpec(m_options.tfSpec, &notes);
        for (const std::string& note : notes)
            std::fprintf(stderr, "splatlab editor: note: %s\n", note.c_str());
        if (!notes.empty())
            m_state.saveNotice = ui::SaveNotice{.text = notes.front(), .folder = {}, .shownAtS = -1.0};
        if (m_options.sessionPath.empty()) return;
        // The session replaces what the flags set; a volume argument replaces the session's volume.
        const std::filesystem::path sessionVolume = ui::loadSession(m_options.sessionPath, m_state);
        m_state.sessionFile = m_options.sessionPath.string();
        if (volumePath.empty()) volumePath = sessionVolume;
    });
    if (m_exitCode == 0 && !m_options.sceneName.empty())
        openDemoScene(m_options.sceneName, m_options.sceneLook, m_options.sceneCamera);
    else if (m_exitCode == 0 && !volumePath.empty())
        openVolume(volumePath, m_options.raw);
    return m_exitCode == 0;
}

bool EditorLoop::checkTabs() const {
    for (const std::string& tab : m_options.tabs)
        if (std::none_of(m_panels.begin(), m_panels.end(),
                         [&](const ui::DockPanel& p) { return p.title == tab; })) {
            std::string titles;
            for (const ui::DockPanel& p : m_panels)
                titles += (titles.empty() ? "" : ", ") + p.title;
            std::fprintf(stderr, "splatlab: --tab: no panel called '%s' (panels: %s)\n", tab.c_str(),
                         titles.c_str());
            return false;
        }
    return true;
}

void EditorLoop::connectSpaceMouse() {
    m_spaceMouse.emplace(ui::makeHidapiBackend());
    m_lastPoll = glfwGetTime(), m_lastSpin = m_lastPoll;
}

void EditorLoop::report(const std::exception& error) {
    if (m_scripted) {
        std::fprintf(stderr, "splatlab editor: %s\n", error.what());
        m_exitCode = 1;
        m_window.close();
    } else {
        m_state.errorMessage = error.what();
    }
}

bool EditorLoop::knobDeflected() const {
    return !m_scripted && m_spaceMouse->connected() && m_state.spaceMouse.enabled &&
           m_spaceMouse->state().deflected();
}

void EditorLoop::waitForInput() {
    // Idle: sleep until an event (the render thread posts one with each image); 16 ms to read a 3D mouse,
    // 50 ms while a job's progress is shown (or the gallery draws), else half a second (for the GPU timers):
    // a UI frame takes the same cores as the render in flight (llvmpipe), so frames nothing asked for slow it
    // down. Scripted, an edit to render, queued input or the knob deflected: keep going.
    if (m_scripted || m_renderPending || m_tfPending || knobDeflected() || m_state.perf.renderContinuously ||
        m_window.inputPending())
        glfwPollEvents();
    else
        glfwWaitEventsTimeout(m_spaceMouse->connected() ? 0.016
                              : m_volumeJob || m_gradientJob || m_comparison || m_gallery.drawing() ||
                                      (m_truth && m_truth->computing()) // a split view's ground truth
                                  ? 0.05
                                  : 0.5);
    m_frameStart = InteractiveProbe::Clock::now();
    if (m_hasScene) m_perfHistory.addTimes(m_render->latestStats());
    takeRenderErrors();
    m_pollTime = glfwGetTime();
    m_spaceMouse->poll(m_pollTime);
    m_state.spaceMouseStatus = m_spaceMouse->status();
    m_knobMoved = false;
    if (knobDeflected() && ui::applyOrbitInput(m_state.camera, ui::spaceMouseOrbit(m_spaceMouse->state(),
                                                                                   m_pollTime - m_lastPoll,
                                                                                   m_state.spaceMouse))) {
        m_renderPending = m_knobMoved = true;
        m_state.preview.lastInput = m_pollTime;
    }
    m_lastPoll = m_pollTime;
}

void EditorLoop::presentFrame(int frame) {
    const auto [fbWidth, fbHeight] = m_window.framebufferSize();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fbWidth, fbHeight);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    guarded([] { renderer::checkGlErrors("editor frame"); });
    if (m_scripted && frame >= m_options.frames && m_exitCode == 0) writeScriptedOutputs(fbWidth, fbHeight);
    m_window.swapBuffers();
    noteReady();
    if (m_probe) {
        const auto now = InteractiveProbe::Clock::now();
        m_probe->uiFrame(std::chrono::duration<double, std::milli>(now - m_frameStart).count(), m_render->busy());
        if (m_probe->finished()) {
            std::vector<double> ms, rmse;
            if (m_shown) ms.assign(m_shown->levelMs.begin(), m_shown->levelMs.end()),
                         rmse.assign(m_shown->levelRmse.begin(), m_shown->levelRmse.end());
            std::printf("%s", m_probe->report(m_doc.volume ? m_doc.volume->name : "none", ms, rmse).c_str());
            m_probe.reset();
            m_window.close();
        }
    }
}

void EditorLoop::noteReady() {
    const char* file = std::getenv("SPLATLAB_READY_FILE");
    if (!file || !m_hasScene || m_volumeJob || m_gradientJob || !m_shown) return;
    if (m_readyNoted && m_finishedImagesNoted == m_finishedImages) return;
    m_readyNoted = true;
    m_finishedImagesNoted = m_finishedImages;
    renderer::writeFileAtomically(file, std::to_string(m_finishedImages) + "\n");
}

void EditorLoop::editForProbe() {
    // Steady state: the volume read and its gradients computed (their workers take the same cores).
    if (!m_probe || !m_hasScene || m_volumeJob || m_gradientJob || !m_probe->editDue(InteractiveProbe::Clock::now()))
        return;
    ui::applyOrbitInput(m_state.camera, {.rotateDxPx = float(10.0 / ui::kOrbitDegPerPx)});
    m_renderPending = true;
    m_probe->editMade(InteractiveProbe::Clock::now());
}

void EditorLoop::saveLayout() {
    if (m_state.configDir.empty()) return;
    try {
        ui::saveDockLayout(m_layout, m_state.configDir);
    } catch (const renderer::LoadError& e) {
        std::fprintf(stderr, "splatlab editor: layout not kept: %s\n", e.what());
    }
}

void EditorLoop::saveSessionTo(const std::filesystem::path& file) {
    if (guarded([&] { ui::saveSession(m_state, m_state.loadedVolume, file); }))
        std::printf("wrote %s\n", file.string().c_str());
    else if (!m_scripted) // no modal left to show it in
        std::fprintf(stderr, "splatlab editor: %s\n", m_state.errorMessage.c_str()), m_exitCode = 1;
}

void EditorLoop::takeRenderErrors() {
    while (const auto error = m_render->takeError()) report(std::runtime_error(*error));
}

void EditorLoop::writeScriptedOutputs(int fbWidth, int fbHeight) {
    if (!m_options.saveImagePath.empty()) {
        startSaveView(m_options.saveImagePath);
        if (const auto written = finishSaveView(true))
            std::printf("wrote %s, %s\n", m_options.saveImagePath.string().c_str(), written->c_str());
    }
    if (!m_options.screenshotPath.empty() && fbWidth > 0 && fbHeight > 0 &&
        guarded([&] { renderer::writeImage(readBackBuffer(fbWidth, fbHeight), m_options.screenshotPath); }))
        std::printf("wrote %s\n", m_options.screenshotPath.string().c_str());
    m_window.close();
}
