// The editor's window: GLFW, its GL 4.5 core context and ImGui's backends, opened and closed in the
// right order. The editor's state and its frame steps are in editor_loop.h.
#include "editor_window.h"

#include "renderer/errors.h"
#include "renderer/gl/gl_context.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <cfloat>
#include <cstdio>
#include <deque>
#include <string>
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
    for (int i = 0; i < count; ++i)
        g_dropped.emplace_back(paths[i]);
}

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

// GLFW's input callbacks: each event goes into the window's queue (EditorWindow::newImGuiFrame hands it
// to ImGui); focus and the pointer entering go to ImGui's backend, which tracks them.
ui::InputQueue& queueOf(GLFWwindow* window) {
    return *static_cast<ui::InputQueue*>(glfwGetWindowUserPointer(window));
}
void onCursorPos(GLFWwindow* w, double x, double y) { queueOf(w).push({.kind = ui::InputEvent::Kind::MouseMove, .x = x, .y = y}); }
void onMouseButton(GLFWwindow* w, int button, int action, int) {
    queueOf(w).push({.kind = ui::InputEvent::Kind::MouseButton, .code = button, .down = action == GLFW_PRESS});
}
void onKey(GLFWwindow* w, int key, int, int action, int) {
    if (action == GLFW_REPEAT) action = GLFW_PRESS; // held: ImGui repeats by itself
    queueOf(w).push({.kind = ui::InputEvent::Kind::Key, .code = key, .down = action == GLFW_PRESS});
}
void onChar(GLFWwindow* w, unsigned c) { queueOf(w).push({.kind = ui::InputEvent::Kind::Char, .code = int(c)}); }
void onScroll(GLFWwindow* w, double dx, double dy) {
    queueOf(w).push({.kind = ui::InputEvent::Kind::Scroll, .x = dx, .y = dy});
}

} // namespace

bool EditorWindow::open(int width, int height, bool vsync) {
    // 1. Window with a GL 4.5 core context, made current; KHR_debug collects GL errors from here on.
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        std::fprintf(stderr, "splatlab editor: cannot open a window: %s (is DISPLAY set? try xvfb-run)\n",
                     g_glfwError.c_str());
        return false;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
#ifndef NDEBUG
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
    m_window = glfwCreateWindow(width, height, "SplatLab", nullptr, nullptr);
    if (!m_window) {
        std::fprintf(stderr,
                     "splatlab editor: cannot open a %dx%d window with an OpenGL 4.5 core context: %s\n",
                     width, height, g_glfwError.c_str());
        return false;
    }
    glfwMakeContextCurrent(m_window);
    glfwSwapInterval(vsync ? 1 : 0);
    renderer::installGlDebugCallback();

    // 2. ImGui: context, dark theme, GLFW input and OpenGL3 drawing backends.
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    m_imguiContext = true;
    ImGui::GetIO().IniFilename = nullptr; // the layout is ours (ui::DockLayout), nothing to persist
    applyTheme();
    m_imguiGlfw = ImGui_ImplGlfw_InitForOpenGL(m_window, false); // its input comes through m_input
    glfwSetWindowUserPointer(m_window, &m_input);
    glfwSetCursorPosCallback(m_window, onCursorPos);
    glfwSetMouseButtonCallback(m_window, onMouseButton);
    glfwSetKeyCallback(m_window, onKey);
    glfwSetCharCallback(m_window, onChar);
    glfwSetScrollCallback(m_window, onScroll);
    glfwSetWindowFocusCallback(m_window, ImGui_ImplGlfw_WindowFocusCallback);
    glfwSetCursorEnterCallback(m_window, ImGui_ImplGlfw_CursorEnterCallback);
    glfwSetDropCallback(m_window, onDrop);
    m_imguiGl = m_imguiGlfw && ImGui_ImplOpenGL3_Init("#version 450");
    if (!m_imguiGl) {
        std::fprintf(stderr, "splatlab editor: ImGui's GLFW/OpenGL3 backends failed to initialise on %s\n",
                     renderer::glVersionString().c_str());
        return false;
    }
    return true;
}

EditorWindow::~EditorWindow() {
    if (m_imguiGl) ImGui_ImplOpenGL3_Shutdown();
    if (m_imguiGlfw) ImGui_ImplGlfw_Shutdown();
    if (m_imguiContext) ImGui::DestroyContext();
    if (m_window) glfwDestroyWindow(m_window);
    glfwTerminate();
}

bool EditorWindow::shouldClose() const { return glfwWindowShouldClose(m_window); }

void EditorWindow::close() { glfwSetWindowShouldClose(m_window, GLFW_TRUE); }

void EditorWindow::setTitle(const std::filesystem::path& volume) {
    glfwSetWindowTitle(m_window, ("SplatLab \xE2\x80\x94 " + volume.stem().string()).c_str());
}

std::pair<int, int> EditorWindow::framebufferSize() const {
    int width = 0, height = 0;
    glfwGetFramebufferSize(m_window, &width, &height);
    return {width, height};
}

void EditorWindow::swapBuffers() { glfwSwapBuffers(m_window); }

void EditorWindow::newImGuiFrame() {
    ImGui_ImplGlfw_NewFrame(); // display size, time, cursor shape; the pointer where it is now
    const ui::FrameInput in = m_input.takeFrame();
    ImGuiIO& io = ImGui::GetIO();
    // The queue's pointer, not the current one: with a change queued, where that change happened. The
    // backend's -FLT_MAX (the pointer left the window) stays.
    if (in.hasMouse && io.MousePos.x != -FLT_MAX) io.MousePos = ImVec2(float(in.mouseX), float(in.mouseY));
    for (int b = 0; b < ui::FrameInput::kButtons; ++b)
        io.MouseDown[b] = in.buttons[size_t(b)];
    for (int k = 0; k < ui::FrameInput::kKeys && k < IM_ARRAYSIZE(io.KeysDown); ++k)
        io.KeysDown[k] = in.keys[size_t(k)];
    io.KeyCtrl = in.keys[GLFW_KEY_LEFT_CONTROL] || in.keys[GLFW_KEY_RIGHT_CONTROL];
    io.KeyShift = in.keys[GLFW_KEY_LEFT_SHIFT] || in.keys[GLFW_KEY_RIGHT_SHIFT];
    io.KeyAlt = in.keys[GLFW_KEY_LEFT_ALT] || in.keys[GLFW_KEY_RIGHT_ALT];
    io.KeySuper = in.keys[GLFW_KEY_LEFT_SUPER] || in.keys[GLFW_KEY_RIGHT_SUPER];
    io.MouseWheel += float(in.scrollY);
    io.MouseWheelH += float(in.scrollX);
    for (unsigned c : in.chars)
        io.AddInputCharacter(c);
}

std::optional<std::filesystem::path> EditorWindow::takeDroppedFile() {
    if (g_dropped.empty()) return std::nullopt;
    std::filesystem::path file = std::move(g_dropped.front());
    g_dropped.pop_front();
    return file;
}

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
