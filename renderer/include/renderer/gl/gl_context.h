// Headless OpenGL 4.5 core through EGL: the NVIDIA EGL device platform when one is present, Mesa's
// surfaceless platform otherwise (llvmpipe on machines without a GPU). Also the KHR_debug hook that
// every GL user shares: errors are collected, and checkGlErrors() turns them into GlError.
#pragma once
#include <memory>
#include <string>
#include <vector>

namespace renderer {

class HeadlessGl {
public:
    // Creates and makes current a 4.5 core context with no surface. Throws GlError with the reason.
    // SPLATLAB_EGL_PLATFORM=surfaceless|device forces a platform.
    static std::unique_ptr<HeadlessGl> create();
    ~HeadlessGl();
    HeadlessGl(const HeadlessGl&) = delete;
    HeadlessGl& operator=(const HeadlessGl&) = delete;

    const std::string& platform() const { return m_platform; }   // "device" or "surfaceless"
    void makeCurrent();

private:
    HeadlessGl() = default;
    void* m_display = nullptr;
    void* m_context = nullptr;
    std::string m_platform;
};

// GL_RENDERER and GL_VERSION of the current context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
std::string glRendererName();
std::string glVersionString();

// Installs a synchronous KHR_debug callback on the current context (idempotent per context).
void installGlDebugCallback();
// Messages of type error (and GL_OUT_OF_MEMORY) seen since the last call; clears them.
std::vector<std::string> takeGlErrors();
// Throws GlError naming `stage` when takeGlErrors() or glGetError() report anything.
void checkGlErrors(const char* stage);

} // namespace renderer
