// Step 3 of a frame and the passes both paths share: bucket selection (the indirect draw commands), the
// cleared targets, patch classification, the splat program's uniforms and bindings, and the X-ray resolve.
#include "splat_renderer_state.h"

#include "renderer/oracle/near_layer.h"

#include <cmath>
#include <limits>

#include <glm/gtc/type_ptr.hpp>

namespace renderer {

void setShadingUniforms(GLuint p, const ShadingParams& sp) {
    glUniform1f(glGetUniformLocation(p, "uShadingParams.ambient"), float(sp.ambient));
    glUniform1f(glGetUniformLocation(p, "uShadingParams.diffuse"), float(sp.diffuse));
    glUniform1f(glGetUniformLocation(p, "uShadingParams.specular"), float(sp.specular));
    glUniform1f(glGetUniformLocation(p, "uShadingParams.shininess"), float(sp.shininess));
    glUniform1f(glGetUniformLocation(p, "uShadingParams.flatGradient"), float(sp.flatGradient));
}

void SplatRenderer::Gl::prepareFrame(FramePlan& f) {
    Gl& g = *this;
    const ImagePlane& plane = f.plane;
    const SplatSettings& settings = f.settings;
    const AxisBuffers& axis = f.lists;
    const Traversal& trav = f.trav;
    const bool tiles = f.tiles, earlyTermination = f.earlyTermination, sheets = f.sheets, xray = f.xray;
    const bool reversed = f.reversed;
    const int variant = f.variant, pointSlices = f.pointSlices;
    const FilterMode drawnFilter = f.drawnFilter;
    const float guard = f.guard;
    const glm::dmat3& varianceCamera = f.varianceCamera;
    // 3a. Bucket selection: the indirect draw commands of the active buckets, in the frame's order.
    if (tiles) g.updateCommands(trav.axis, false, false, settings.drawAllBuckets);
    else g.updateCommands(trav.axis, f.descending, reversed, settings.drawAllBuckets);

    // 3b. Cleared image, heatmap, depth and counters; both targets only with the heatmap.
    const float zero[4] = {0, 0, 0, 0};
    const float one = 1.0f;
    glDisable(GL_SCISSOR_TEST);
    glClearNamedFramebufferfv(g.frameFbo, GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(g.frameFbo, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(g.frameFbo, GL_DEPTH, 0, &one);
    if (settings.counters) glClearNamedBufferData(g.counterBuffer, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    const GLenum bothTargets[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    const GLsizei targets = settings.heatmap ? 2 : 1;
    glNamedFramebufferDrawBuffers(g.frameFbo, targets, bothTargets);
    glNamedFramebufferDrawBuffers(g.sheetFbo, targets, bothTargets);

    // 3c. Adaptive: each patch's filter.
    if (settings.filter == FilterMode::Adaptive) {
        g.classifyPatches(plane, settings, trav.axis, drawnFilter);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    // 3d. The splat (or tile record) program of the frame's variant, its uniforms and bindings.
    const GLuint p = f.program =
        tiles ? g.tileProgram(Gl::kTileSplat, variant & ~kHeatmap) : g.splatProgram(variant);
    g.useProgram(p);
    glBindTextureUnit(8, g.patchTexture);
    g.setCommonUniforms(p, plane, settings, trav.axis);
    glUniform1i(glGetUniformLocation(p, "uFilter"), int(drawnFilter));
    const glm::mat3 varCamera(varianceCamera);
    const double meanSpacing = (g.spacing.x + g.spacing.y + g.spacing.z) / 3.0;
    const double diagonal = std::hypot(double(plane.width), double(plane.height));
    glUniform2f(glGetUniformLocation(p, "uCentrePx"), float(plane.centrePx.x), float(plane.centrePx.y));
    glUniform2f(glGetUniformLocation(p, "uViewport"), float(plane.width), float(plane.height));
    glUniform1f(glGetUniformLocation(p, "uGuardPx"), guard);
    glUniformMatrix3fv(glGetUniformLocation(p, "uVarCamera"), 1, GL_FALSE, glm::value_ptr(varCamera));
    glUniform1f(glGetUniformLocation(p, "uCutoff"), float(settings.cutoffSigmas));
    glUniform1f(glGetUniformLocation(p, "uNearReach"), float(splatNearReach(plane, settings)));
    glUniform1f(glGetUniformLocation(p, "uExtinctionScale"),
                float(settings.density / meanSpacing * g.spacing.x * g.spacing.y * g.spacing.z /
                      footprintMassWithin(settings.cutoffSigmas)));   // unit mass inside the cutoff (ewa.h)
    glUniform1f(glGetUniformLocation(p, "uMaxHalfExtent"), settings.maxFootprintFraction > 0.0
                                                                 ? float(settings.maxFootprintFraction * diagonal)
                                                                 : std::numeric_limits<float>::infinity());
    glUniform1i(glGetUniformLocation(p, "uAdditive"), sheets || xray);
    glUniform1i(glGetUniformLocation(p, "uReverse"), reversed);
    glUniform1i(glGetUniformLocation(p, "uTilesX"), g.tiles.x);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, g.opaqueTiles);   // updateOpaqueTiles() writes it
    g.bindCullMap(g.opaqueTiles);
    if (earlyTermination) {   // nothing is opaque yet
        const GLuint zeroWord = 0;
        glClearNamedBufferData(g.opaqueTiles, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zeroWord);
    }
    const ShadingParams& sp = settings.shadingParams;
    setShadingUniforms(p, sp);
    glUniform1f(glGetUniformLocation(p, "uSurfaceFlatten"), float(settings.surfaceFlatten));
    glUniform1f(glGetUniformLocation(p, "uSurfaceGradient"), float(settings.surfaceGradient));
    const glm::dvec3 sigma = settings.kernelScale * g.spacing;
    glUniform3f(glGetUniformLocation(p, "uSigma"), float(sigma.x), float(sigma.y), float(sigma.z));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, g.gradientBuffer);
    glBindTextureUnit(0, g.classTexture);
    glBindTextureUnit(4, g.lutTexture);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, axis.entries);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, g.counterBuffer);
    glBindVertexArray(g.splatVao);
    glVertexArrayVertexBuffer(g.splatVao, 0, axis.runs, 0, sizeof(glm::uvec4));
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, g.commands);
    // 3e. Rasteriser state: point sizes, the guard band, blending.
    if (pointSlices > 0) glEnable(GL_PROGRAM_POINT_SIZE);
    const int guardInt = int(guard);
    glViewport(-guardInt, -guardInt, plane.width + 2 * guardInt, plane.height + 2 * guardInt);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
}

// Rewrites the indirect commands for the current LUT, axis and order (GPU only: nothing is
// uploaded). Tiles read them ascending, by run.
void SplatRenderer::Gl::updateCommands(int axis, bool descending, bool reversed, bool allBuckets) {
    const CommandsKey key{lutVersion, axis, allBuckets, descending, reversed};
    const AxisBuffers& a = axes[size_t(axis)];
    if (commandsKey == key || a.runCount == 0) return;
    lap(GpuPass::Select);
    useProgram(commandsProgram);
    glUniform1i(glGetUniformLocation(commandsProgram, "uAllBuckets"), allBuckets);
    glUniform1i(glGetUniformLocation(commandsProgram, "uDescending"), descending);
    glUniform1i(glGetUniformLocation(commandsProgram, "uReversed"), reversed);
    glUniform1ui(glGetUniformLocation(commandsProgram, "uRuns"), a.runCount);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, a.runs);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, lutBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, a.sliceRunsBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, commands);
    glDispatchCompute((a.runCount + 63) / 64, 1, 1);
    glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    commandsKey = key;
}

// The adaptive classifier once per patch (compute) into patchTexture; returns the patch count. Where
// uniformAdaptiveFilter() decided the view (`decided`, else Adaptive), every patch is set to that
// filter, what the pass would give, so hysteresis reads it next frame.
size_t SplatRenderer::Gl::classifyPatches(const ImagePlane& plane, const SplatSettings& settings, int axis,
                       FilterMode decided) {
    lap(GpuPass::Patches);
    const PatchGrid grid = patchGrid(dims, axis, settings.patchSize);
    const size_t n = grid.count();
    if (const glm::ivec3 size{grid.columns, grid.rows, grid.slices}; size != patchTextureSize) {
        glDeleteTextures(1, &patchTexture);
        glCreateTextures(GL_TEXTURE_3D, 1, &patchTexture);
        glTextureStorage3D(patchTexture, 1, GL_R8UI, size.x, size.y, size.z);
        patchTextureSize = glm::ivec3(0);   // until made: a failure leaves none, and the next frame tries again
        checkGpuAllocation("patch modes texture", n);
        glTextureParameteri(patchTexture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);   // else incomplete (integer)
        glTextureParameteri(patchTexture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        patchTextureSize = size;
        patchLayout.reset();
    }
    if (decided != FilterMode::Adaptive) {
        const GLubyte mode = GLubyte(decided);
        glClearTexImage(patchTexture, 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &mode);
    } else {
        useProgram(patchProgram);
        setCommonUniforms(patchProgram, plane, settings, axis);
        glUniform1i(glGetUniformLocation(patchProgram, "uNa"), grid.columns);
        glUniform1i(glGetUniformLocation(patchProgram, "uNb"), grid.rows);
        glUniform1i(glGetUniformLocation(patchProgram, "uSlices"), grid.slices);
        glUniform1i(glGetUniformLocation(patchProgram, "uHasPrevious"), patchLayout == grid);
        glBindImageTexture(0, patchTexture, 0, GL_TRUE, 0, GL_READ_WRITE, GL_R8UI);
        glDispatchCompute(GLuint((n + 63) / 64), 1, 1);
    }
    patchLayout = settings.filter == FilterMode::Adaptive ? std::optional(grid) : std::nullopt;
    return n;
}

// Uniforms of SPLAT_COMMON for this view.
void SplatRenderer::Gl::setCommonUniforms(GLuint p, const ImagePlane& plane, const SplatSettings& settings,
                                          int axis) const {
    const glm::mat3 w(plane.viewFromObject);
    // Positions relative to the volume's origin, folded into the translation in double: a volume
    // far from the world origin (1e6 units) keeps its sub-voxel precision in float.
    const glm::dvec3 translation = plane.viewFromObject * origin + plane.translation;
    const AdaptiveThresholds t = adaptiveThresholds(spacing, plane, settings);
    glUniform3i(glGetUniformLocation(p, "uDims"), dims.x, dims.y, dims.z);
    glUniform3f(glGetUniformLocation(p, "uSpacing"), float(spacing.x), float(spacing.y), float(spacing.z));
    glUniformMatrix3fv(glGetUniformLocation(p, "uViewFromObject"), 1, GL_FALSE, glm::value_ptr(w));
    glUniform3f(glGetUniformLocation(p, "uTranslation"), float(translation.x), float(translation.y),
                float(translation.z));
    glUniform1f(glGetUniformLocation(p, "uFPx"), float(plane.fPx));
    glUniform1f(glGetUniformLocation(p, "uNear"), float(plane.nearDepth));
    glUniform1i(glGetUniformLocation(p, "uFilter"), int(settings.filter));
    glUniform1i(glGetUniformLocation(p, "uOrtho"), plane.orthographic);
    glUniform1i(glGetUniformLocation(p, "uAxis"), axis);
    const int patchSize = std::max(settings.patchSize, 1);
    glUniform1i(glGetUniformLocation(p, "uPatchSize"), patchSize);
    glUniform1f(glGetUniformLocation(p, "uInvPatchSize"), 1.0f / float(patchSize));
    glUniform1f(glGetUniformLocation(p, "uReconAbovePx"), float(t.reconstructionAbovePx));
    glUniform1f(glGetUniformLocation(p, "uLowPassBelowPx"), float(t.lowPassBelowPx));
    glUniform1f(glGetUniformLocation(p, "uSigmaMin"), float(t.sigmaMin));
    glUniform1f(glGetUniformLocation(p, "uSigmaMax"), float(t.sigmaMax));
    glUniform1f(glGetUniformLocation(p, "uHysteresis"), float(settings.hysteresis));
}

// X-ray's sums become 1 - exp(-sum), in place (xray_resolve.frag).
void SplatRenderer::Gl::resolveXRay(int w, int h) {
    lap(GpuPass::Resolve);
    glBindFramebuffer(GL_FRAMEBUFFER, frameFbo);
    glDisable(GL_BLEND);
    glViewport(0, 0, w, h);
    glTextureBarrier();
    useProgram(resolveProgram);
    glBindTextureUnit(2, image);
    glBindTextureUnit(3, heat);
    glBindVertexArray(emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

} // namespace renderer
