// Early termination and occlusion culling: the opaque-pixel mask of rasterised front-to-back frames and the
// opaque-tile map splats are culled against (opaque_tiles.comp, opaque_tiles_read.glsl).
#include "splat_renderer_state.h"

namespace renderer {

// Whether any tile of the opaque-tile map is opaque (a wait for the passes before it).
bool SplatRenderer::Gl::anyTileOpaque() {
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint flag = 0;
    readBuffer(opaqueTiles, GLintptr(size_t(tiles.x) * size_t(tiles.y) * 4), 4, &flag);
    return flag != 0;
}

// The opaque-tile map (binding 11) from the image's alpha: what occlusion culling reads.
void SplatRenderer::Gl::updateOpaqueTiles(float opaqueAlpha) {
    useProgram(opaqueTilesProgram);
    glUniform1f(glGetUniformLocation(opaqueTilesProgram, "uOpaqueAlpha"), opaqueAlpha);
    glUniform2i(glGetUniformLocation(opaqueTilesProgram, "uTiles"), tiles.x, tiles.y);
    glBindTextureUnit(2, image);
    glDispatchCompute(GLuint((tiles.x + 7) / 8), GLuint((tiles.y + 7) / 8), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
}

// The opaque-tile map occlusion culling reads (opaque_tiles_read.glsl).
void SplatRenderer::Gl::bindCullMap(GLuint map) {
    bindTexels(opaqueTexture, GL_R32UI, map, GLsizeiptr(opaqueMapBytes()), 7);
}

// Front to back, every `refresh` slices: pixels whose alpha reached opaqueAlpha get depth 0.5,
// where splats (also at 0.5) fail GL_LESS; the tile map the vertex stage culls with is redone
// once every occlusionSlices(settings) slices (`remap`).
void SplatRenderer::Gl::maskOpaquePixels(const FramePlan& f, GLuint fbo, bool remap) {
    Gl& g = *this;
    const ImagePlane& plane = f.plane;
    const SplatSettings& settings = f.settings;
    const GLuint p = f.program;
    g.lap(GpuPass::Opaque);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, plane.width, plane.height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    g.useProgram(g.opaqueMaskProgram);
    glUniform1f(glGetUniformLocation(g.opaqueMaskProgram, "uOpaqueAlpha"), float(settings.opaqueAlpha));
    glBindTextureUnit(2, g.image);
    glBindVertexArray(g.emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (remap) g.updateOpaqueTiles(float(settings.opaqueAlpha));
    // Back to splatting: at depth 0.5 against the mask, blending, the splat program.
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    g.useProgram(p);
    glBindVertexArray(g.splatVao);
}

} // namespace renderer
