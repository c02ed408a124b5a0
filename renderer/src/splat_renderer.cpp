// The GL splatting path (see splat_renderer.h). One non-indexed draw of 6 vertices per splat: the
// vertex stage fetches the voxel index from the visible list, rebuilds the footprint exactly as
// splatGeometry() does on the CPU (same formulas, float instead of double) and emits a quad around
// the cutoff ellipse; the fragment stage evaluates the Gaussian at the pixel centre.
#include "renderer/splat_renderer.h"

#include "gl_util.h"
#include "renderer/classifier.h"
#include "renderer/errors.h"
#include "renderer/gl_context.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <optional>

namespace renderer {

namespace {

const char* kSplatVert = R"(#version 450 core
layout(std430, binding = 0) readonly buffer VisibleList { uint visible[]; };
layout(std430, binding = 1) readonly buffer LutBuffer { vec4 lut[]; };
layout(binding = 0) uniform usampler3D classes;      // per-voxel LUT class (R16UI)

uniform uint uCount;          // splats in the list
uniform bool uDescending;     // walk the list from its end (back to front)
uniform ivec3 uDims;
uniform vec3 uSpacing;        // object position of voxel ijk is origin + spacing * ijk
uniform mat3 uViewFromObject; // W
uniform vec3 uTranslation;    // W origin + d: camera position of voxel (0,0,0)
uniform float uFPx;
uniform vec2 uCentrePx, uViewport;
uniform float uNear;
uniform mat3 uVarCamera;      // W V'' W^T, shared by every voxel of a rectilinear grid
uniform int uFilter;          // 0 reconstruction, 1 low-pass, 2 EWA, 3 adaptive (classifier.h)
uniform bool uOrtho;          // constant affine projection diag(f, f, 1)
uniform int uAxis;            // traversal axis: patches lie in its slices
uniform int uPatchSize;
uniform float uReconAbovePx, uLowPassBelowPx, uSigmaMin, uSigmaMax;
uniform float uCutoff;        // in sigmas
uniform float uExtinctionScale;   // density / mean spacing * voxel volume
uniform float uMaxHalfExtent;     // huge-footprint guard, pixels

flat out vec2 vCentre;
flat out vec3 vConic;         // (a, b, c): e = a dx^2 + 2 b dx dy + c dy^2
flat out float vAmplitude;
flat out vec3 vColour;

int classifyDepth(float u2) {
    if (!uOrtho && !(u2 > uNear)) return 0;
    float pxPerUnit = uOrtho ? uFPx : uFPx / u2;
    if (uSigmaMin * pxPerUnit > uReconAbovePx) return 0;
    if (uSigmaMax * pxPerUnit < uLowPassBelowPx) return 1;
    return 2;
}

// The patch's filter from its four corner voxels, as classifyPatch() does on the CPU.
int classifyPatch(ivec3 ijk) {
    int a = (uAxis + 1) % 3, b = (uAxis + 2) % 3;
    int a0 = ijk[a] / uPatchSize * uPatchSize, b0 = ijk[b] / uPatchSize * uPatchSize;
    int a1 = min(a0 + uPatchSize - 1, uDims[a] - 1), b1 = min(b0 + uPatchSize - 1, uDims[b] - 1);
    int mode = 2;
    for (int corner = 0; corner < 4; ++corner) {
        ivec3 c = ijk;
        c[a] = (corner & 1) != 0 ? a1 : a0;
        c[b] = (corner & 2) != 0 ? b1 : b0;
        int m = classifyDepth((uViewFromObject * (uSpacing * vec3(c)) + uTranslation).z);
        if (corner == 0) mode = m;
        else if (m != mode) return 2;
    }
    return mode;
}

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);   // culled unless a footprint is emitted below
    uint k = uint(gl_VertexID) / 6u;
    uint voxel = visible[uDescending ? uCount - 1u - k : k];
    ivec3 ijk = ivec3(int(voxel % uint(uDims.x)), int((voxel / uint(uDims.x)) % uint(uDims.y)),
                      int(voxel / uint(uDims.x * uDims.y)));
    uint cls = texelFetch(classes, ijk, 0).r;
    vec4 tf = lut[cls];

    vec3 u = uViewFromObject * (uSpacing * vec3(ijk)) + uTranslation;
    if (!(u.z > uNear)) return;
    float l = length(u);
    float iz = 1.0 / u.z;
    // Pixel-unit Jacobian (001 eq. 25), written row by row, transposed into GLSL's column order;
    // orthographic: the constant affine map.
    mat3 J = uOrtho ? mat3(uFPx, 0.0, 0.0, 0.0, uFPx, 0.0, 0.0, 0.0, 1.0)
                    : transpose(mat3(uFPx * iz, 0.0, -uFPx * u.x * iz * iz,
                                     0.0, uFPx * iz, -uFPx * u.y * iz * iz,
                                     u.x / l, u.y / l, u.z / l));
    mat3 V = J * uVarCamera * transpose(J);
    mat2 vHat = mat2(V[0][0], V[0][1], V[1][0], V[1][1]);
    int mode = uFilter == 3 ? classifyPatch(ijk) : uFilter;
    mat2 M = mode == 0 ? vHat : (mode == 1 ? mat2(1.0) : vHat + mat2(1.0));
    float det = M[0][0] * M[1][1] - M[0][1] * M[1][0];
    if (!(det > 1e-12)) return;
    vec2 halfExtent = uCutoff * sqrt(vec2(M[0][0], M[1][1]));
    if (max(halfExtent.x, halfExtent.y) > uMaxHalfExtent) return;

    float detJ = uOrtho ? uFPx * uFPx : uFPx * uFPx * l * iz * iz * iz;
    vCentre = uCentrePx + uFPx * (uOrtho ? u.xy : u.xy * iz);
    vConic = vec3(M[1][1], -M[0][1], M[0][0]) / det;
    vAmplitude = tf.a * uExtinctionScale * detJ / (6.283185307 * sqrt(det));
    vColour = tf.rgb;
    // One pixel of margin: the fragment test, not the quad, decides coverage.
    vec2 p = vCentre + kCorners[gl_VertexID % 6] * (halfExtent + 1.0);
    gl_Position = vec4(2.0 * p.x / uViewport.x - 1.0, 1.0 - 2.0 * p.y / uViewport.y, 0.0, 1.0);
}
)";

const char* kSplatFrag = R"(#version 450 core
flat in vec2 vCentre;
flat in vec3 vConic;
flat in float vAmplitude;
flat in vec3 vColour;
uniform vec2 uViewport;
uniform float uCutoff;
uniform bool uXray;
out vec4 fragColour;

void main() {
    vec2 d = vec2(gl_FragCoord.x, uViewport.y - gl_FragCoord.y) - vCentre;   // y down, like the CPU
    float e = vConic.x * d.x * d.x + 2.0 * vConic.y * d.x * d.y + vConic.z * d.y * d.y;
    if (e > uCutoff * uCutoff) discard;
    float tau = vAmplitude * exp(-0.5 * e);
    if (uXray) {
        fragColour = vec4(vColour * tau, tau);
    } else {
        // 1 - exp(-tau) loses all digits in float for tiny tau; the series is exact to 1e-10 there.
        float a = tau < 1e-3 ? tau * (1.0 - 0.5 * tau) : 1.0 - exp(-tau);
        fragColour = vec4(vColour * a, a);
    }
}
)";

const char* kFullscreenVert = R"(#version 450 core
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// X-ray resolve: the accumulated sums become 1 - exp(-sum), like the CPU oracle.
const char* kResolveFrag = R"(#version 450 core
layout(binding = 0) uniform sampler2D accum;
out vec4 fragColour;
void main() {
    vec4 s = texelFetch(accum, ivec2(gl_FragCoord.xy), 0);
    fragColour = vec4(1.0) - exp(-s);
}
)";

// Display: composite over the background and flip, so memory row 0 is the image's top row.
const char* kDisplayFrag = R"(#version 450 core
layout(binding = 0) uniform sampler2D image;
uniform vec3 uBackground;
out vec4 fragColour;
void main() {
    ivec2 size = textureSize(image, 0);
    vec4 c = texelFetch(image, ivec2(gl_FragCoord.x, size.y - 1 - int(gl_FragCoord.y)), 0);
    fragColour = vec4(c.rgb + (1.0 - c.a) * uBackground, 1.0);
}
)";

constexpr int kTimerRing = 4;

constexpr uint64_t kMiB = uint64_t(1) << 20;

// Free GPU memory as the driver reports it (GL_NVX_gpu_memory_info, GL_ATI_meminfo); std::nullopt
// when neither extension is there (Mesa llvmpipe, Intel): only GL_OUT_OF_MEMORY can tell then.
std::optional<uint64_t> freeGpuMemoryBytes() {
    GLint kib[4] = {0, 0, 0, 0};
    if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
        glGetIntegerv(GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX, kib);
        return uint64_t(kib[0]) * 1024;
    }
    if (epoxy_has_gl_extension("GL_ATI_meminfo")) {
        glGetIntegerv(GL_TEXTURE_FREE_MEMORY_ATI, kib);   // [0]: total free in the pool, KiB
        return uint64_t(kib[0]) * 1024;
    }
    return std::nullopt;
}

std::string memoryMessage(const std::string& name, uint64_t needed, std::optional<uint64_t> freeBytes,
                          const std::string& detail) {
    const std::string freeText =
        freeBytes ? std::to_string(*freeBytes / kMiB) + " MiB free" : "free memory unknown";
    return (name.empty() ? std::string("volume") : name) + ": needs " +
           std::to_string((needed + kMiB - 1) / kMiB) + " MiB of GPU memory, " + freeText + detail;
}

// Right after a GPU allocation: GL_OUT_OF_MEMORY (from glGetError or KHR_debug) becomes a RenderError
// saying how much the scene needs; other GL errors stay GlErrors.
void checkAllocation(const char* what, const std::string& name, uint64_t needed,
                     std::optional<uint64_t> freeBytes) {
    std::vector<std::string> errors = takeGlErrors();
    bool outOfMemory = false;
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
        outOfMemory |= e == GL_OUT_OF_MEMORY;
        errors.push_back("glGetError " + std::to_string(e));
    }
    for (const std::string& e : errors) {
        std::string lowered = e;
        std::transform(lowered.begin(), lowered.end(), lowered.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        outOfMemory |= lowered.find("out of memory") != std::string::npos ||
                       lowered.find("out_of_memory") != std::string::npos;
    }
    if (outOfMemory)
        throw RenderError(
            memoryMessage(name, needed, freeBytes, std::string(" (GL_OUT_OF_MEMORY allocating the ") + what + ")"));
    if (!errors.empty()) {
        std::string all;
        for (const auto& e : errors) all += (all.empty() ? "" : "; ") + e;
        throw GlError(std::string("SplatRenderer::setScene ") + what, all);
    }
}

} // namespace

struct SplatRenderer::Gl {
    GLuint splatProgram = 0, resolveProgram = 0, displayProgram = 0;
    GLuint vao = 0;
    GLuint classTexture = 0;
    GLuint lutBuffer = 0;
    std::array<GLuint, 3> visibleBuffers{};
    std::array<uint32_t, 3> visibleCounts{};
    GLuint resultTexture = 0, accumTexture = 0, displayTex = 0;
    GLuint resultFbo = 0, accumFbo = 0, displayFbo = 0;
    int width = 0, height = 0;
    std::array<GLuint, kTimerRing> timers{};
    std::array<bool, kTimerRing> timerPending{};
    std::array<uint64_t, kTimerRing> timerFrame{};
    uint64_t frameCounter = 0, newestTimed = 0;
    int timerNext = 0;
    // Scene constants the vertex stage needs.
    glm::ivec3 dims{0};
    glm::dvec3 origin{0.0}, spacing{1.0};
    uint64_t sceneBytes = 0;
    uint64_t memoryLimit = 0;   // setMemoryLimit(); 0: none beyond what the driver reports

    ~Gl() {
        glDeleteProgram(splatProgram);
        glDeleteProgram(resolveProgram);
        glDeleteProgram(displayProgram);
        glDeleteVertexArrays(1, &vao);
        glDeleteTextures(1, &classTexture);
        glDeleteBuffers(1, &lutBuffer);
        glDeleteBuffers(3, visibleBuffers.data());
        releaseTargets();
        glDeleteQueries(kTimerRing, timers.data());
    }

    void releaseTargets() {
        const GLuint textures[] = {resultTexture, accumTexture, displayTex};
        const GLuint fbos[] = {resultFbo, accumFbo, displayFbo};
        glDeleteTextures(3, textures);
        glDeleteFramebuffers(3, fbos);
        resultTexture = accumTexture = displayTex = resultFbo = accumFbo = displayFbo = 0;
    }

    static void makeTarget(GLenum format, int w, int h, GLuint& texture, GLuint& fbo) {
        glCreateTextures(GL_TEXTURE_2D, 1, &texture);
        glTextureStorage2D(texture, 1, format, w, h);
        glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glCreateFramebuffers(1, &fbo);
        glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, texture, 0);
        if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw GlError("render target", "framebuffer incomplete for a " + std::to_string(w) + "x" +
                                               std::to_string(h) + " target");
    }

    void ensureTargets(int w, int h) {
        if (w == width && h == height && resultTexture) return;
        releaseTargets();
        makeTarget(GL_RGBA32F, w, h, resultTexture, resultFbo);
        makeTarget(GL_RGBA32F, w, h, accumTexture, accumFbo);
        makeTarget(GL_RGBA8, w, h, displayTex, displayFbo);
        width = w;
        height = h;
    }
};

SplatRenderer::SplatRenderer() : m_gl(std::make_unique<Gl>()) {
    if (epoxy_gl_version() < 45)
        throw GlError("SplatRenderer", "needs OpenGL 4.5 core, the current context has " + glVersionString());
    installGlDebugCallback();
    m_gl->splatProgram = gl::buildProgram("splat", kSplatVert, kSplatFrag);
    m_gl->resolveProgram = gl::buildProgram("xray_resolve", kFullscreenVert, kResolveFrag);
    m_gl->displayProgram = gl::buildProgram("display", kFullscreenVert, kDisplayFrag);
    glCreateVertexArrays(1, &m_gl->vao);
    glCreateQueries(GL_TIME_ELAPSED, kTimerRing, m_gl->timers.data());
    checkGlErrors("SplatRenderer setup");
}

SplatRenderer::~SplatRenderer() = default;

void SplatRenderer::setScene(const SplatScene& scene) {
    Gl& g = *m_gl;
    const glm::ivec3 d = scene.dims;
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSize);
    if (d.x > maxSize || d.y > maxSize || d.z > maxSize)
        throw RenderError("volume dims exceed GL_MAX_3D_TEXTURE_SIZE " + std::to_string(maxSize));
    // GPU memory: the classes (2 bytes a voxel), the LUT and three visible lists, against what the
    // driver reports free (plus what the current scene holds, which is replaced) and the optional limit.
    uint64_t needed = scene.classes.size() * sizeof(uint16_t) + scene.lut.size() * sizeof(glm::vec4);
    for (const auto& list : scene.visible) needed += std::max<size_t>(list.size(), 1) * sizeof(uint32_t);
    std::optional<uint64_t> freeBytes = freeGpuMemoryBytes();
    if (freeBytes) *freeBytes += g.sceneBytes;
    if (g.memoryLimit) freeBytes = std::min(freeBytes.value_or(g.memoryLimit), g.memoryLimit);
    if (freeBytes && needed > *freeBytes) throw RenderError(memoryMessage(scene.name, needed, freeBytes, ""));
    checkGlErrors("SplatRenderer::setScene (before uploading)");

    m_stats.uploadBytes = 0;
    if (g.dims != d || !g.classTexture) {
        glDeleteTextures(1, &g.classTexture);
        glCreateTextures(GL_TEXTURE_3D, 1, &g.classTexture);
        glTextureStorage3D(g.classTexture, 1, GL_R16UI, d.x, d.y, d.z);
        glTextureParameteri(g.classTexture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(g.classTexture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        checkAllocation("class texture", scene.name, needed, freeBytes);
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glTextureSubImage3D(g.classTexture, 0, 0, 0, 0, d.x, d.y, d.z, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                        scene.classes.data());
    m_stats.uploadBytes += scene.classes.size() * sizeof(uint16_t);

    glDeleteBuffers(1, &g.lutBuffer);
    glCreateBuffers(1, &g.lutBuffer);
    glNamedBufferStorage(g.lutBuffer, GLsizeiptr(scene.lut.size() * sizeof(glm::vec4)), scene.lut.data(), 0);
    checkAllocation("LUT buffer", scene.name, needed, freeBytes);
    m_stats.uploadBytes += scene.lut.size() * sizeof(glm::vec4);

    g.sceneBytes = scene.classes.size() * sizeof(uint16_t) + scene.lut.size() * sizeof(glm::vec4);
    for (int axis = 0; axis < 3; ++axis) {
        const auto& list = scene.visible[axis];
        glDeleteBuffers(1, &g.visibleBuffers[axis]);
        glCreateBuffers(1, &g.visibleBuffers[axis]);
        // A zero-sized buffer store is an error; keep one element so an empty scene stays valid.
        const uint32_t dummy = 0;
        const size_t bytes = std::max<size_t>(list.size(), 1) * sizeof(uint32_t);
        glNamedBufferStorage(g.visibleBuffers[axis], GLsizeiptr(bytes), list.empty() ? &dummy : list.data(), 0);
        checkAllocation("visible list", scene.name, needed, freeBytes);
        g.visibleCounts[axis] = uint32_t(list.size());
        m_stats.uploadBytes += bytes;
        g.sceneBytes += bytes;
    }
    g.dims = d;
    g.origin = scene.origin;
    g.spacing = scene.spacing;
    checkGlErrors("SplatRenderer::setScene");
}

void SplatRenderer::render(const ImagePlane& plane, const SplatSettings& settings) {
    Gl& g = *m_gl;
    const auto cpuStart = std::chrono::steady_clock::now();
    if (plane.width < 1 || plane.height < 1 || plane.width > 16384 || plane.height > 16384)
        throw RenderError("image size " + std::to_string(plane.width) + "x" + std::to_string(plane.height) +
                          " out of range (1..16384)");
    if (!g.classTexture) throw RenderError("SplatRenderer::render called before setScene");
    g.ensureTargets(plane.width, plane.height);

    collectTimers();
    const size_t slot = size_t(g.timerNext);
    const bool timed = !g.timerPending[slot];   // ring full of unfinished frames: skip, never stall
    if (timed) glBeginQuery(GL_TIME_ELAPSED, g.timers[slot]);

    const Traversal trav = chooseTraversal(plane);
    if (settings.compositing == Compositing::SheetBackToFront || settings.compositing == Compositing::SheetFrontToBack)
        throw RenderError(std::string(compositingName(settings.compositing)) +
                          " compositing runs on the CPU oracle only so far (use --cpu)");
    const bool xray = settings.compositing == Compositing::XRay;
    const GLuint target = xray ? g.accumFbo : g.resultFbo;
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(target, GL_COLOR, 0, zero);
    glBindFramebuffer(GL_FRAMEBUFFER, target);
    glViewport(0, 0, plane.width, plane.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    if (xray) glBlendFunc(GL_ONE, GL_ONE);                 // order-free sums
    else glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);     // premultiplied "over", back to front

    const GLuint p = g.splatProgram;
    glUseProgram(p);
    const glm::mat3 varCamera(kernelVarianceCamera(settings.kernelScale * g.spacing, plane.viewFromObject));
    const glm::mat3 w(plane.viewFromObject);
    const double meanSpacing = (g.spacing.x + g.spacing.y + g.spacing.z) / 3.0;
    const double diagonal = std::hypot(double(plane.width), double(plane.height));
    const uint32_t count = g.visibleCounts[size_t(trav.axis)];
    glUniform1ui(glGetUniformLocation(p, "uCount"), count);
    glUniform1i(glGetUniformLocation(p, "uDescending"), trav.descending);
    glUniform3i(glGetUniformLocation(p, "uDims"), g.dims.x, g.dims.y, g.dims.z);
    // Positions relative to the volume's origin, folded into the translation in double: a volume far
    // from the world origin (1e6 units) keeps its sub-voxel precision in float.
    const glm::dvec3 translation = plane.viewFromObject * g.origin + plane.translation;
    glUniform3f(glGetUniformLocation(p, "uSpacing"), float(g.spacing.x), float(g.spacing.y), float(g.spacing.z));
    glUniformMatrix3fv(glGetUniformLocation(p, "uViewFromObject"), 1, GL_FALSE, glm::value_ptr(w));
    glUniform3f(glGetUniformLocation(p, "uTranslation"), float(translation.x), float(translation.y),
                float(translation.z));
    glUniform1f(glGetUniformLocation(p, "uFPx"), float(plane.fPx));
    glUniform2f(glGetUniformLocation(p, "uCentrePx"), float(plane.centrePx.x), float(plane.centrePx.y));
    glUniform2f(glGetUniformLocation(p, "uViewport"), float(plane.width), float(plane.height));
    glUniform1f(glGetUniformLocation(p, "uNear"), float(plane.nearDepth));
    glUniformMatrix3fv(glGetUniformLocation(p, "uVarCamera"), 1, GL_FALSE, glm::value_ptr(varCamera));
    glUniform1i(glGetUniformLocation(p, "uFilter"), int(settings.filter));
    const AdaptiveThresholds thresholds = adaptiveThresholds(g.spacing, plane, settings);
    glUniform1i(glGetUniformLocation(p, "uOrtho"), plane.orthographic);
    glUniform1i(glGetUniformLocation(p, "uAxis"), trav.axis);
    glUniform1i(glGetUniformLocation(p, "uPatchSize"), std::max(settings.patchSize, 1));
    glUniform1f(glGetUniformLocation(p, "uReconAbovePx"), float(thresholds.reconstructionAbovePx));
    glUniform1f(glGetUniformLocation(p, "uLowPassBelowPx"), float(thresholds.lowPassBelowPx));
    glUniform1f(glGetUniformLocation(p, "uSigmaMin"), float(thresholds.sigmaMin));
    glUniform1f(glGetUniformLocation(p, "uSigmaMax"), float(thresholds.sigmaMax));
    glUniform1f(glGetUniformLocation(p, "uCutoff"), float(settings.cutoffSigmas));
    glUniform1f(glGetUniformLocation(p, "uExtinctionScale"),
                float(settings.density / meanSpacing * g.spacing.x * g.spacing.y * g.spacing.z));
    glUniform1f(glGetUniformLocation(p, "uMaxHalfExtent"), float(settings.maxFootprintFraction * diagonal));
    glUniform1i(glGetUniformLocation(p, "uXray"), xray);
    glBindTextureUnit(0, g.classTexture);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.visibleBuffers[size_t(trav.axis)]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.lutBuffer);
    glBindVertexArray(g.vao);
    if (count > 0) glDrawArrays(GL_TRIANGLES, 0, GLsizei(count) * 6);

    if (xray) {
        glDisable(GL_BLEND);
        glBindFramebuffer(GL_FRAMEBUFFER, g.resultFbo);
        glUseProgram(g.resolveProgram);
        glBindTextureUnit(0, g.accumTexture);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    if (timed) {
        glEndQuery(GL_TIME_ELAPSED);
        g.timerPending[slot] = true;
        g.timerFrame[slot] = ++g.frameCounter;
        g.timerNext = (g.timerNext + 1) % kTimerRing;
    }
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlErrors("SplatRenderer::render");

    m_stats.splatsDrawn = count;
    m_stats.uploadBytes = 0;   // a frame uploads uniforms only
    m_stats.cpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpuStart).count();
}

void SplatRenderer::collectTimers() {
    Gl& g = *m_gl;
    for (int i = 0; i < kTimerRing; ++i) {
        if (!g.timerPending[size_t(i)]) continue;
        GLint ready = 0;
        glGetQueryObjectiv(g.timers[size_t(i)], GL_QUERY_RESULT_AVAILABLE, &ready);
        if (!ready) continue;
        GLuint64 ns = 0;
        glGetQueryObjectui64v(g.timers[size_t(i)], GL_QUERY_RESULT, &ns);
        g.timerPending[size_t(i)] = false;
        if (g.timerFrame[size_t(i)] > g.newestTimed) {   // keep the newest finished frame's time
            g.newestTimed = g.timerFrame[size_t(i)];
            m_stats.gpuMs = double(ns) * 1e-6;
        }
    }
}

Image SplatRenderer::readback() const {
    const Gl& g = *m_gl;
    Image img(g.width, g.height);
    if (!g.resultTexture) return img;
    std::vector<float> raw(img.rgba.size());
    glGetTextureImage(g.resultTexture, 0, GL_RGBA, GL_FLOAT, GLsizei(raw.size() * sizeof(float)), raw.data());
    const size_t row = size_t(g.width) * 4;
    for (int y = 0; y < g.height; ++y)   // GL's row 0 is the bottom
        std::copy_n(&raw[size_t(g.height - 1 - y) * row], row, &img.rgba[size_t(y) * row]);
    checkGlErrors("SplatRenderer::readback");
    return img;
}

unsigned SplatRenderer::displayTexture(const float background[3]) {
    Gl& g = *m_gl;
    if (!g.resultTexture) return 0;
    glBindFramebuffer(GL_FRAMEBUFFER, g.displayFbo);
    glViewport(0, 0, g.width, g.height);
    glDisable(GL_BLEND);
    glUseProgram(g.displayProgram);
    glUniform3f(glGetUniformLocation(g.displayProgram, "uBackground"), background[0], background[1], background[2]);
    glBindTextureUnit(0, g.resultTexture);
    glBindVertexArray(g.vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlErrors("SplatRenderer::displayTexture");
    return g.displayTex;
}

uint64_t SplatRenderer::sceneBytes() const { return m_gl->sceneBytes; }

void SplatRenderer::setMemoryLimit(uint64_t bytes) { m_gl->memoryLimit = bytes; }

} // namespace renderer
