// The editor's window: GLFW with a GL 4.5 core context, ImGui's context with its GLFW and OpenGL3
// backends and the theme, the files dropped on it, and its back buffer. Knows nothing of volumes.
#pragma once
#include "renderer/io/image.h"
#include "ui/input_queue.h"

#include <filesystem>
#include <optional>
#include <utility>

struct GLFWwindow;

class EditorWindow {
  public:
    EditorWindow() = default;
    EditorWindow(const EditorWindow&) = delete;
    EditorWindow& operator=(const EditorWindow&) = delete;
    // Shuts ImGui's backends down while the window and its context still exist, then closes GLFW.
    ~EditorWindow();

    // Opens a `width` x `height` window with its context current (KHR_debug collects GL errors from
    // here on) and ImGui on it. Returns false after printing one line to stderr.
    bool open(int width, int height, bool vsync);

    GLFWwindow* handle() const { return m_window; }
    bool shouldClose() const;
    void close();                                       // the frame loop ends after this frame
    void setTitle(const std::filesystem::path& volume); // "SplatLab — <volume's stem>"
    std::pair<int, int> framebufferSize() const;        // pixels, not screen coordinates
    // ImGui's GLFW backend's new frame, with the mouse and keys from the input queue: a frame sees at most
    // one button or key change, with the pointer where it happened (ui/input_queue.h).
    void newImGuiFrame();
    bool inputPending() const { return !m_input.empty(); } // events wait for the next frames
    void swapBuffers();
    // The oldest file dropped on the window and not yet taken; the frame loop opens one a frame.
    std::optional<std::filesystem::path> takeDroppedFile();

  private:
    GLFWwindow* m_window = nullptr;
    ui::InputQueue m_input; // GLFW's input events, which its callbacks queue instead of ImGui's
    bool m_imguiContext = false, m_imguiGlfw = false, m_imguiGl = false; // what the destructor shuts down
};

// The default framebuffer's back buffer as an opaque Image, row 0 at the top (GL's row 0 is the bottom).
renderer::Image readBackBuffer(int width, int height);
