// EGL headless contexts and the KHR_debug error collector (see gl_context.h).
#include "renderer/gl/gl_context.h"

#include "renderer/errors.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <utility>

namespace renderer {

namespace {

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const size_t n = std::strlen(name);
    for (const char* p = std::strstr(list, name); p; p = std::strstr(p + 1, name))
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

std::string eglErrorString() {
    char buf[32];
    std::snprintf(buf, sizeof buf, "EGL error 0x%04x", eglGetError());
    return buf;
}

// The first EGL device whose driver is NVIDIA's (it exposes EGL_NV_device_cuda), or null.
EGLDeviceEXT findNvidiaDevice() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hasExtension(client, "EGL_EXT_device_enumeration") || !hasExtension(client, "EGL_EXT_platform_device"))
        return nullptr;
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!eglQueryDevicesEXT(16, devices, &count)) return nullptr;
    for (EGLint i = 0; i < count; ++i)
        if (hasExtension(eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS), "EGL_NV_device_cuda")) return devices[i];
    return nullptr;
}

std::mutex g_errorMutex;
std::vector<std::string> g_errors;

void GLAPIENTRY onGlDebugMessage(GLenum, GLenum type, GLuint id, GLenum severity, GLsizei length,
                                 const GLchar* message, const void*) {
    // Collected, not thrown: unwinding through the driver's C frames is undefined behaviour.
    if (type != GL_DEBUG_TYPE_ERROR && severity != GL_DEBUG_SEVERITY_HIGH) return;
    std::lock_guard lock(g_errorMutex);
    g_errors.push_back("GL debug #" + std::to_string(id) + ": " +
                       std::string(message, length > 0 ? size_t(length) : std::strlen(message)));
}

} // namespace

std::unique_ptr<HeadlessGl> HeadlessGl::create() {
    const char* force = std::getenv("SPLATLAB_EGL_PLATFORM");
    const std::string forced = force ? force : "";
    if (!forced.empty() && forced != "device" && forced != "surfaceless")
        throw GlError("EGL", "SPLATLAB_EGL_PLATFORM=" + forced + ": unknown platform (known: device, surfaceless)");

    std::unique_ptr<HeadlessGl> gl(new HeadlessGl());
    EGLDisplay display = EGL_NO_DISPLAY;
    if (forced != "surfaceless") {
        if (EGLDeviceEXT device = findNvidiaDevice()) {
            display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
            gl->m_platform = "device";
        } else if (forced == "device") {
            throw GlError("EGL", "SPLATLAB_EGL_PLATFORM=device but no NVIDIA EGL device was found");
        }
    }
    if (display == EGL_NO_DISPLAY) {
        if (!hasExtension(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS), "EGL_MESA_platform_surfaceless"))
            throw GlError("EGL", "no EGL_MESA_platform_surfaceless (install libegl-mesa0 libgl1-mesa-dri)");
        display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        gl->m_platform = "surfaceless";
    }
    if (display == EGL_NO_DISPLAY) throw GlError("EGL", "eglGetPlatformDisplay failed: " + eglErrorString());
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) throw GlError("EGL", "eglInitialize failed: " + eglErrorString());
    gl->m_display = display;
    if (!eglBindAPI(EGL_OPENGL_API)) throw GlError("EGL", "eglBindAPI(OpenGL) failed: " + eglErrorString());

    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
        const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
        EGLint n = 0;
        if (!eglChooseConfig(display, want, &config, 1, &n) || n < 1)
            throw GlError("EGL", "no EGL config supports desktop OpenGL");
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE, EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attribs);
    if (context == EGL_NO_CONTEXT)
        throw GlError("EGL", "cannot create an OpenGL 4.5 core context on the " + gl->m_platform +
                                 " platform: " + eglErrorString());
    gl->m_context = context;
    gl->makeCurrent();
    installGlDebugCallback();
    return gl;
}

HeadlessGl::~HeadlessGl() {
    if (!m_display) return;
    eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (m_context) eglDestroyContext(m_display, m_context);
    eglTerminate(m_display);
}

void HeadlessGl::makeCurrent() {
    if (!eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context))
        throw GlError("EGL", "eglMakeCurrent failed: " + eglErrorString());
}

std::string glRendererName() {
    const auto* s = glGetString(GL_RENDERER);
    return s ? reinterpret_cast<const char*>(s) : "unknown";
}

std::string glVersionString() {
    const auto* s = glGetString(GL_VERSION);
    return s ? reinterpret_cast<const char*>(s) : "unknown";
}

void installGlDebugCallback() {
    if (epoxy_gl_version() < 43 && !epoxy_has_gl_extension("GL_KHR_debug")) return;
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(onGlDebugMessage, nullptr);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
}

std::vector<std::string> takeGlErrors() {
    std::lock_guard lock(g_errorMutex);
    return std::exchange(g_errors, {});
}

void checkGlErrors(const char* stage) {
    auto errors = takeGlErrors();
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
        char buf[48];
        std::snprintf(buf, sizeof buf, "glGetError 0x%04x", e);
        errors.emplace_back(buf);
    }
    if (errors.empty()) return;
    std::string all;
    for (const auto& e : errors) all += (all.empty() ? "" : "; ") + e;
    throw GlError(stage, all);
}

} // namespace renderer
