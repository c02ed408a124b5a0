// runEditor: the editor's page. Opens the window, starts the editor from the flags (or a session), then
// runs the frame loop; each step is an EditorLoop method (editor_loop.h) and the window is EditorWindow's.
#include "editor.h"

#include "editor_loop.h"
#include "editor_window.h"

#include <csignal>
#include <cstdio>
#include <memory>

namespace {

// SIGINT or SIGTERM: the loop closes the window once the input queued before it is taken (and writes
// --session-out).
volatile std::sig_atomic_t g_closeRequested = 0;
void requestClose(int) { g_closeRequested = 1; }

} // namespace

int runEditor(const EditorOptions& options) {
    const bool scripted = options.frames > 0; // runs N frames and exits; errors end it with code 1

    // 1. Window with a GL 4.5 core context and ImGui on it (vsync off in scripted runs). Declared first,
    //    so it outlives the editor's GL objects.
    EditorWindow window;
    if (!window.open(options.width, options.height, /*vsync=*/!scripted)) return 1;

    // 2. The editor's state from the flags, then the session file they name; the volume starts loading.
    //    The renderer starts on its own thread with its own GL context.
    std::unique_ptr<EditorLoop> started;
    try {
        started = std::make_unique<EditorLoop>(options, window);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "splatlab editor: %s\n", e.what());
        return 1;
    }
    EditorLoop& editor = *started;
    if (!editor.start()) return editor.exitCode();
    if (!editor.checkTabs()) return 1;
    editor.connectSpaceMouse();

    std::signal(SIGINT, requestClose);
    std::signal(SIGTERM, requestClose);

    // 3. Frame loop. Edits made in frame N are rendered at the top of frame N+1, at the viewport size
    //    frame N measured; the first frame only measures.
    for (int frame = 1; !window.shouldClose(); ++frame) {
        editor.waitForInput();          // a. events (or a nap while idle), GPU timers, 3D mouse
        editor.applyEdits();            // b. last frame's edits: volumes, TF, window, gradients
        editor.stepFilterMeasurement(); // c. Filters > Measure: start, cancel, one setting more
        editor.renderViewport();        // d. frame, spin, render the view (or its preview)
        editor.drawPanels(frame);       // e. ImGui frame: the panels and modals record edits
        editor.noteEdits();             // f. what the edits ask of the next frame: probe, render
        editor.presentFrame(frame);     // g. UI to the back buffer, on screen; scripted outputs
        if (g_closeRequested && !window.inputPending()) window.close(); // input made before it, seen first
    }
    editor.saveLayout();
    if (!options.sessionOutPath.empty()) editor.saveSessionTo(options.sessionOutPath);
    return editor.exitCode();
}
