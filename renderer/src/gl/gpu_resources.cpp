// The GL objects SplatRenderer::Gl owns: render targets, growable buffers, buffer textures, teardown.
#include "splat_renderer_state.h"

#include "renderer/out_of_memory.h"

#include <cctype>
#include <iterator>

namespace renderer {

bool takeOutOfMemory(const std::string& stage) {
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
    if (outOfMemory) return true;
    if (!errors.empty()) {
        std::string all;
        for (const auto& e : errors) all += (all.empty() ? "" : "; ") + e;
        throw GlError(stage, all);
    }
    return false;
}

std::string SplatRenderer::Gl::frameText() const {
    return framePx.x > 0 ? " at " + std::to_string(framePx.x) + "x" + std::to_string(framePx.y) : std::string();
}

void SplatRenderer::Gl::checkGpuAllocation(const char* what, uint64_t bytes) const {
    if (takeOutOfMemory(std::string("allocating the ") + what))
        throw outOfMemory(volumeSubject(sceneName), what, bytes, frameText(), Memory::Gpu);
}

SplatRenderer::Gl::~Gl() {
    for (auto [bits, p] : splatPrograms) glDeleteProgram(p);
    for (auto [bits, p] : tilePrograms) glDeleteProgram(p);
    deleteWorkingBuffers();
    glDeleteBuffers(1, &savedCounters);
    for (StatusSlot& slot : statusSlots) {
        glDeleteBuffers(1, &slot.buffer);
        if (slot.fence) glDeleteSync(slot.fence);
    }
    glDeleteBuffers(1, &scatterArgs);
    glDeleteTextures(1, &tileListTexture);
    glDeleteTextures(1, &tileSplatTexture);
    glDeleteTextures(1, &opaqueTexture);
    glDeleteTextures(1, &tileStateTexture);
    for (GLuint p : {compositePrograms[0], compositePrograms[1], opaqueMaskProgram, resolveProgram, displayProgram,
                     commandsProgram, patchProgram, opaqueTilesProgram, nearKernelsProgram, nearLayerProgram})
        glDeleteProgram(p);
    glDeleteFramebuffers(1, &computeFbo);
    const GLuint vaos[] = {splatVao, emptyVao};
    glDeleteVertexArrays(2, vaos);
    glDeleteTextures(1, &classTexture);
    glDeleteTextures(1, &lutTexture);
    glDeleteTextures(1, &tf2dTexture);
    glDeleteTextures(1, &patchTexture);
    const GLuint buffers[] = {lutBuffer, counterBuffer, gradientBuffer, commands, nearBuffer};
    glDeleteBuffers(5, buffers);
    for (auto& a : axes) a.release();
    releaseTargets();
    for (Laps& l : laps) glDeleteQueries(GLsizei(l.queries.size()), l.queries.data());
    glDeleteQueries(1, &fragmentQuery);
}

void SplatRenderer::Gl::releaseTargets() {
    const GLuint textures[] = {image, heat, sheet, sheetHeat, depth, displayTex};
    const GLuint fbos[] = {frameFbo, sheetFbo, displayFbo, depthFbo};
    glDeleteTextures(6, textures);
    glDeleteFramebuffers(4, fbos);
    glDeleteBuffers(1, &opaqueTiles);
    image = heat = sheet = sheetHeat = depth = displayTex = frameFbo = sheetFbo = displayFbo = depthFbo = 0;
    opaqueTiles = 0;
}

GLuint SplatRenderer::Gl::makeTexture(GLenum format, int w, int h) {
    GLuint texture = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, format, w, h);
    glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return texture;
}

GLuint SplatRenderer::Gl::makeFbo(std::initializer_list<GLuint> colours, GLuint depthTexture) {
    GLuint fbo = 0;
    glCreateFramebuffers(1, &fbo);
    GLenum attachment = GL_COLOR_ATTACHMENT0;
    for (GLuint c : colours) glNamedFramebufferTexture(fbo, attachment++, c, 0);
    if (depthTexture) glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, depthTexture, 0);
    if (colours.size() == 0) glNamedFramebufferDrawBuffer(fbo, GL_NONE);
    if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw GlError("render target", "framebuffer incomplete");
    return fbo;
}

void SplatRenderer::Gl::ensureTargets(int w, int h) {
    if (w == width && h == height && image) return;
    releaseTargets();
    width = height = 0;   // until every target is made: a failure leaves none, and the next frame tries again
    // Four RGBA32F images (image, heatmap, their sheets), 32-bit depth and the 8-bit display image.
    const uint64_t bytes = uint64_t(w) * uint64_t(h) * (4 * 16 + 4 + 4);
    const auto made = [&] {
        if (!takeOutOfMemory("render targets")) return;
        releaseTargets();
        throw outOfMemory(volumeSubject(sceneName), "render targets", bytes,
                          " at " + std::to_string(w) + "x" + std::to_string(h), Memory::Gpu);
    };
    image = makeTexture(GL_RGBA32F, w, h);
    heat = makeTexture(GL_RGBA32F, w, h);
    sheet = makeTexture(GL_RGBA32F, w, h);
    sheetHeat = makeTexture(GL_RGBA32F, w, h);
    depth = makeTexture(GL_DEPTH_COMPONENT32F, w, h);
    displayTex = makeTexture(GL_RGBA8, w, h);
    glTextureParameteri(displayTex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(displayTex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    made();   // before the framebuffers, which a missing texture leaves incomplete
    frameFbo = makeFbo({image, heat}, depth);
    sheetFbo = makeFbo({sheet, sheetHeat}, depth);
    displayFbo = makeFbo({displayTex}, 0);
    depthFbo = makeFbo({}, depth);   // the opaque mask of splat-every-sample: reads the image
    tiles = glm::ivec2((w + kOpaqueTilePx - 1) / kOpaqueTilePx, (h + kOpaqueTilePx - 1) / kOpaqueTilePx);
    glCreateBuffers(1, &opaqueTiles);
    glNamedBufferStorage(opaqueTiles, GLsizeiptr(opaqueMapBytes()), nullptr, 0);
    made();
    width = w;
    height = h;
}

void SplatRenderer::Gl::deleteWorkingBuffers() {
    const GLuint buffers[] = {tileSplats, tileBins, tileState, tileList, tileBusy, chunkStartMap};
    glDeleteBuffers(GLsizei(std::size(buffers)), buffers);
    tileSplats = tileBins = tileState = tileList = tileBusy = chunkStartMap = 0;
    tileSplatBytes = tileBinBytes = tileStateBytes = tileListBytes = tileBusyBytes = chunkStartMapBytes = 0;
}

void SplatRenderer::Gl::releaseWorkingBuffers() {
    deleteWorkingBuffers();
    // The lists' high-water mark was the other volume's, and so are the figures its frames still owe
    // (taken now, so that they cannot raise the mark again).
    for (StatusSlot& slot : statusSlots) takeStatus(slot, nullptr);
    listCapacity = 0;
}

// Grows `buffer` to at least `bytes` (with headroom); its contents are not kept.
void SplatRenderer::Gl::ensureBuffer(GLuint& buffer, size_t& capacity, size_t bytes, const char* what) {
    if (bytes <= capacity && buffer) return;
    glDeleteBuffers(1, &buffer);
    const size_t grown = std::max<size_t>(bytes + bytes / 4, 64);
    capacity = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, GLsizeiptr(grown), nullptr, 0);
    try {
        checkGpuAllocation(what, grown);
    } catch (...) {
        glDeleteBuffers(1, &buffer);
        buffer = 0;
        throw;
    }
    capacity = grown;
}

// Binds to `unit` the buffer texture `texture` (created on first use) over the first `bytes` of
// `buffer`: llvmpipe fetches texels lane by lane as a gather, storage-buffer values component by
// component, so the passes read what they do not write as texels.
void SplatRenderer::Gl::bindTexels(GLuint& texture, GLenum format, GLuint buffer, GLsizeiptr bytes,
                                   GLuint unit) {
    if (!texture) glCreateTextures(GL_TEXTURE_BUFFER, 1, &texture);
    glTextureBufferRange(texture, format, buffer, 0, bytes);
    glBindTextureUnit(unit, texture);
}

} // namespace renderer
