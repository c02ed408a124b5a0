// The GL splatting path (see splat_renderer.h). Rasterised: one point (or 6 vertices) per splat; the
// vertex stage fetches the voxel index from the visible list, rebuilds the footprint exactly as
// splatGeometry() does on the CPU (same formulas, float instead of double) and emits a point or quad
// around the cutoff ellipse; the fragment stage evaluates the Gaussian at the pixel centre. Tiled
// (sheets and X-ray): compute passes build the same footprints, bin them to screen tiles and
// composite each tile's pixels in registers (renderer/shaders/tile_*.comp).
// This file: construction, render() and the steps of drawFrame(), read-back; the steps live beside it.
#include "splat_renderer_state.h"

#include "renderer/gl/driver_profile.h"
#include "renderer/out_of_memory.h"

#include <chrono>
#include <exception>
#include <utility>

namespace renderer {

SplatRenderer::SplatRenderer() : m_gl(std::make_unique<Gl>()) {
    if (epoxy_gl_version() < 45)
        throw GlError("SplatRenderer", "needs OpenGL 4.5 core, the current context has " + glVersionString());
    installGlDebugCallback();
    Gl& g = *m_gl;
    g.splatProgram(0);   // the common variant: a broken shader fails here, not in the first frame
    g.buildFixedPrograms();
    glCreateVertexArrays(1, &g.splatVao);
    glCreateVertexArrays(1, &g.emptyVao);
    // Attribute 0: the run record, one per draw (divisor 1 reads element baseInstance).
    glEnableVertexArrayAttrib(g.splatVao, 0);
    glVertexArrayAttribIFormat(g.splatVao, 0, 4, GL_UNSIGNED_INT, 0);
    glVertexArrayAttribBinding(g.splatVao, 0, 0);
    glVertexArrayBindingDivisor(g.splatVao, 0, 1);
    glCreateQueries(GL_SAMPLES_PASSED, 1, &g.fragmentQuery);
    glCreateBuffers(1, &g.counterBuffer);
    glNamedBufferStorage(g.counterBuffer, kCounterSlots * sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);
    GLfloat pointRange[2] = {1, 1};
    glGetFloatv(GL_ALIASED_POINT_SIZE_RANGE, pointRange);
    g.maxPointSize = GLint(pointRange[1]);
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &g.maxTexelBuffer);
    glCreateFramebuffers(1, &g.computeFbo);
    g.driver = driverProfile(glRendererName());
    g.loopLimit = measureLoopLimit();
    checkGlErrors("SplatRenderer setup");
}

SplatRenderer::~SplatRenderer() = default;

void SplatRenderer::render(const ImagePlane& plane, const SplatSettings& settings) {
    // The frame's size in the messages of allocations that fail while drawing it.
    struct FrameScope {
        Gl& g;
        ~FrameScope() { g.framePx = glm::ivec2(0); }
    } scope{*m_gl};
    m_gl->framePx = glm::ivec2(plane.width, plane.height);
    m_gl->lastRequest.emplace(plane, settings);
    std::string refused;
    try {
        refused = drawFrame(plane, settings, false);
        // Auto: one slice's tile lists did not fit; the same frame through the rasteriser, with tiles'
        // semantics.
        if (!refused.empty() && settings.primitive == SplatSettings::Primitive::Auto)
            refused = drawFrame(plane, settings, true);
    } catch (const std::bad_alloc&) {   // host memory: the GPU's failures name their buffer themselves
        throw outOfMemory(volumeSubject(m_gl->sceneName), "frame's working data", 0, m_gl->frameText());
    }
    if (!refused.empty()) throw RenderError(refused);
}

std::string SplatRenderer::drawFrame(const ImagePlane& plane, const SplatSettings& settings, bool rasterise) {
    Gl& g = *m_gl;
    const auto cpuStart = std::chrono::steady_clock::now();
    // 1. Decide the frame: the view's axis (made resident), variant, tiles or raster, each slice's
    //    primitive (frame_plan.cpp). Throws on what it cannot draw, before anything is issued.
    FramePlan f = g.planFrame(plane, settings, rasterise);
    g.interrupted = false;
    // What finished deferred frames left (no wait); the frame before is superseded by this one.
    g.pollStatus();
    g.statusLatest = -1;
    g.readBacks = 0;
    m_stats.redone = false;
    // 2. Start the timers and the fragment query. What throws below is held until they end: a query left
    //    active would break the next frame (NVIDIA keeps a deleted active query running).
    collectTimers();
    g.beginTiming(settings, m_stats);
    std::string refused;   // why this frame could not be drawn, when only drawing it tells
    std::exception_ptr failed;   // e.g. a buffer that could not grow: thrown once the queries ended
    try {
        // 3. Select the buckets, clear the targets, classify the patches, bind the splat program
        //    (frame_passes.cpp).
        g.prepareFrame(f);
        // 4. Splat the slices: compute passes per screen tile, or the rasteriser.
        m_stats.slicesDrawn = 0;
        m_stats.tileEntries = 0;
        m_stats.tileListSplits = 0;
        if (f.tiles) refused = g.drawTiled(f, m_stats);
        else g.drawRasterised(f, m_stats);
        // 4b. The kernels at the near plane, integrated along the rays, in front (near_layer_pass.cpp).
        g.nearDrawn = false;
        if (refused.empty() && !g.interrupted) g.drawNearLayer(f);
    } catch (...) {
        failed = std::current_exception();
    }
    // 5. End the timers and the query.
    g.endTiming(f);
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (failed) {
        takeGlErrors();   // what the failed allocation left; the next frame starts clean
        while (glGetError() != GL_NO_ERROR) {}
        std::rethrow_exception(failed);
    }
    checkGlErrors("SplatRenderer::render");
    if (!refused.empty()) return refused;   // found mid-frame: reported once the queries ended
    if (g.interrupted) throw Cancelled("SplatRenderer::render: interrupted; the image is incomplete");

    // 6. What was drawn; with counters, wait for the frame and read them back.
    m_stats.splatsDrawn = f.submitted;
    m_stats.pointSlices = f.pointSlices;
    m_stats.quadSlices = int(std::count(f.sliceDraw.begin(), f.sliceDraw.end(), kQuads));
    m_stats.tiles = f.tiles;
    m_stats.adaptiveAs = settings.filter == FilterMode::Adaptive ? f.drawnFilter : FilterMode::Adaptive;
    m_stats.uploadBytes = f.listUpload;   // uniforms, and the lists when the view's axis changed
    m_stats.frameUploadBytes = g.uploadedSinceFrame + f.listUpload;
    g.uploadedSinceFrame = 0;
    m_stats.hasCounters = settings.counters;
    if (settings.counters) g.readCounters(m_stats);   // for tests, benchmarks and the stats panel's opt-in
    m_stats.readBacks = g.readBacks;
    if (settings.counters) settleFrame();   // the counters waited for the frame: its figures too
    m_stats.firstUsePrograms = g.firstUses;
    m_stats.cpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpuStart).count();
    return {};
}

std::vector<uint8_t> SplatRenderer::patchModes(const ImagePlane& plane, const SplatSettings& settings) {
    Gl& g = *m_gl;
    if (!g.classTexture) throw RenderError("SplatRenderer::patchModes called before setScene");
    const size_t n = g.classifyPatches(plane, settings, chooseTraversal(plane).axis);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    std::vector<uint8_t> modes = namingAllocation(volumeSubject(g.sceneName), "patch modes", n, "",
                                                  [&] { return std::vector<uint8_t>(n); });
    glPixelStorei(GL_PACK_ALIGNMENT, 1);   // rows of any number of patches, unpadded
    glGetTextureImage(g.patchTexture, 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, GLsizei(n), modes.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    checkGlErrors("SplatRenderer::patchModes");
    return modes;
}

namespace {

// `what` and `sceneName` name the image in the message when its memory runs out.
Image readTexture(GLuint texture, int w, int h, const char* what, const std::string& sceneName) {
    const size_t floats = size_t(w) * size_t(h) * 4;
    std::vector<float> raw;
    Image img = namingAllocation(volumeSubject(sceneName), what, 2 * floats * sizeof(float),
                                 " at " + std::to_string(w) + "x" + std::to_string(h), [&] {
                                     Image made(w, h);
                                     if (texture) raw.resize(floats);
                                     return made;
                                 });
    if (!texture) return img;
    glGetTextureImage(texture, 0, GL_RGBA, GL_FLOAT, GLsizei(raw.size() * sizeof(float)), raw.data());
    const size_t row = size_t(w) * 4;
    for (int y = 0; y < h; ++y)   // GL's row 0 is the bottom
        std::copy_n(&raw[size_t(h - 1 - y) * row], row, &img.rgba[size_t(y) * row]);
    checkGlErrors("SplatRenderer::readback");
    return img;
}

} // namespace

void SplatRenderer::settleFrame() {
    Gl& g = *m_gl;
    if (g.statusLatest < 0) return;
    Gl::StatusSlot& slot = g.statusSlots[size_t(g.statusLatest)];
    g.statusLatest = -1;
    if (!g.takeStatus(slot, &m_stats) || !g.lastRequest) return;
    // Its lists were too short (or a run was cut short): the same frame again, the checked way, once,
    // to the end (an interrupt would leave no image at all).
    struct Restore {
        Gl& g;
        std::function<bool()> interrupt;
        ~Restore() {
            g.checkedFrame = false;
            g.interrupt = std::move(interrupt);
        }
    } restore{g, std::exchange(g.interrupt, {})};
    g.checkedFrame = true;
    const auto [plane, settings] = *g.lastRequest;
    render(plane, settings);
    m_stats.redone = true;
}

Image SplatRenderer::readback() {
    settleFrame();
    return readTexture(m_gl->image, m_gl->width, m_gl->height, "read-back image", m_gl->sceneName);
}

Image SplatRenderer::readbackHeatmap() {
    settleFrame();
    return readTexture(m_gl->heat, m_gl->width, m_gl->height, "read-back heatmap", m_gl->sceneName);
}

unsigned SplatRenderer::displayTexture(const float background[3], bool heatmap) {
    settleFrame();
    Gl& g = *m_gl;
    if (!g.image) return 0;
    glBindFramebuffer(GL_FRAMEBUFFER, g.displayFbo);
    glViewport(0, 0, g.width, g.height);
    glDisable(GL_BLEND);
    g.useProgram(g.displayProgram);
    glUniform3f(glGetUniformLocation(g.displayProgram, "uBackground"), background[0], background[1], background[2]);
    glBindTextureUnit(0, heatmap ? g.heat : g.image);
    glBindVertexArray(g.emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlErrors("SplatRenderer::displayTexture");
    return g.displayTex;
}

uint64_t SplatRenderer::sceneBytes() const { return m_gl->sceneBytes; }
uint64_t SplatRenderer::workingBytes() const {
    const Gl& g = *m_gl;
    return g.tileSplatBytes + g.tileBinBytes + g.tileStateBytes + g.tileListBytes + g.tileBusyBytes +
           g.chunkStartMapBytes + g.savedCounterBytes;
}

void SplatRenderer::setMemoryLimit(uint64_t bytes) { m_gl->memoryLimit = bytes; }
void SplatRenderer::setTexelBufferLimit(uint64_t texels) { m_gl->texelLimit = texels; }
void SplatRenderer::setListChunkSlices(uint32_t slices) { m_gl->listChunkSlicesSet = slices; }
void SplatRenderer::setCompositePerPixel(bool perPixel) { m_gl->driver.compositePerPixel = perPixel; }
void SplatRenderer::setDeferredListChecks(bool deferred) { m_gl->driver.deferredListChecks = deferred; }
void SplatRenderer::setInterrupt(std::function<bool()> interrupted) { m_gl->interrupt = std::move(interrupted); }

} // namespace renderer
