// Step 4b of a frame: the near layer (renderer/oracle/near_layer.h) on the GPU. A compute pass gathers
// the kernels at the near plane from the voxels around the eye (near_kernels.comp); a full-screen pass
// integrates them along each pixel's ray and composites the layer in front of the splats
// (near_layer.frag). Nothing runs when the near plane meets no voxel's kernel.
#include "splat_renderer_state.h"

#include "renderer/oracle/near_layer.h"
#include "renderer/oracle/ray_kernel.h"

#include <glm/gtc/type_ptr.hpp>

namespace renderer {

namespace {
constexpr GLsizeiptr kNearHeaderBytes = 16;                    // count and padding
constexpr GLsizeiptr kNearKernelBytes = 2 * sizeof(glm::vec4); // centre and extinction, colour
} // namespace

void SplatRenderer::Gl::drawNearLayer(const FramePlan& f) {
    const ImagePlane& plane = f.plane;
    const SplatSettings& settings = f.settings;
    nearDrawn = false;
    if (!hasNearLayer(plane, settings)) return;
    const NearTest test = nearTest(spacing, plane, settings);
    const VoxelBox box = nearCandidates(dims, origin, spacing, plane, test);
    if (box.empty()) return;
    if (!nearBuffer) {
        glCreateBuffers(1, &nearBuffer);
        glNamedBufferStorage(nearBuffer, kNearHeaderBytes + kMaxNearKernels * kNearKernelBytes, nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
    }
    const GLuint zero = 0;
    glClearNamedBufferSubData(nearBuffer, GL_R32UI, 0, kNearHeaderBytes, GL_RED_INTEGER, GL_UNSIGNED_INT,
                              &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, nearBuffer);

    // 1. Gather: one invocation a candidate voxel (looping where the box needs more groups than a dispatch).
    useProgram(nearKernelsProgram);
    setCommonUniforms(nearKernelsProgram, plane, settings, f.trav.axis);
    const glm::ivec3 size = box.hi - box.lo + 1;
    glUniform3i(glGetUniformLocation(nearKernelsProgram, "uBoxLo"), box.lo.x, box.lo.y, box.lo.z);
    glUniform3i(glGetUniformLocation(nearKernelsProgram, "uBoxSize"), size.x, size.y, size.z);
    const glm::mat3 varCamera(f.varianceCamera); // the splat stage's uniform, bit for bit
    glUniformMatrix3fv(glGetUniformLocation(nearKernelsProgram, "uVarCamera"), 1, GL_FALSE,
                       glm::value_ptr(varCamera));
    glUniform1f(glGetUniformLocation(nearKernelsProgram, "uCutoff"), float(settings.cutoffSigmas));
    glUniform1f(glGetUniformLocation(nearKernelsProgram, "uNearReach"),
                float(splatNearReach(plane, settings)));
    glUniform1f(glGetUniformLocation(nearKernelsProgram, "uRadius"), float(test.radius));
    glm::vec3 sides[4];
    for (int s = 0; s < 4; ++s)
        sides[s] = glm::vec3(test.sides[size_t(s)]);
    glUniform3fv(glGetUniformLocation(nearKernelsProgram, "uSides"), 4, glm::value_ptr(sides[0]));
    const double meanSpacing = (spacing.x + spacing.y + spacing.z) / 3.0;
    glUniform1f(glGetUniformLocation(nearKernelsProgram, "uExtinctionPerOpacity"),
                float(settings.density / meanSpacing));
    glUniform1i(glGetUniformLocation(nearKernelsProgram, "uGradientOpacity"), gradientOpacity && hasGradients);
    glUniform1i(glGetUniformLocation(nearKernelsProgram, "uTf2d"), tf2d && hasGradients);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, gradientBuffer);
    glBindTextureUnit(0, classTexture);
    glBindTextureUnit(4, lutTexture);
    glDispatchCompute(GLuint(std::min<uint64_t>((box.count() + 63) / 64, 65535)), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    // 2. The layer over the image (X-ray: onto its resolved sums), the image target only.
    glBindFramebuffer(GL_FRAMEBUFFER, frameFbo);
    glNamedFramebufferDrawBuffer(frameFbo, GL_COLOR_ATTACHMENT0);
    glViewport(0, 0, plane.width, plane.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, f.xray ? GL_ONE_MINUS_SRC_COLOR : GL_ONE_MINUS_SRC_ALPHA);
    useProgram(nearLayerProgram);
    const glm::dvec3 sigma = settings.kernelScale * spacing;
    const glm::dmat3 w = plane.viewFromObject;
    glm::dmat3 invVarObject(0.0);
    for (int a = 0; a < 3; ++a)
        invVarObject[a][a] = 1.0 / (sigma[a] * sigma[a]);
    const glm::mat3 invVarCamera(w * invVarObject * glm::transpose(w));
    glUniform2f(glGetUniformLocation(nearLayerProgram, "uCentrePx"), float(plane.centrePx.x),
                float(plane.centrePx.y));
    glUniform1f(glGetUniformLocation(nearLayerProgram, "uFPx"), float(plane.fPx));
    glUniform1f(glGetUniformLocation(nearLayerProgram, "uNear"), float(plane.nearDepth));
    glUniform1f(glGetUniformLocation(nearLayerProgram, "uHeight"), float(plane.height));
    glUniformMatrix3fv(glGetUniformLocation(nearLayerProgram, "uInvVarCamera"), 1, GL_FALSE,
                       glm::value_ptr(invVarCamera));
    glUniform1f(glGetUniformLocation(nearLayerProgram, "uCut2"),
                float(settings.cutoffSigmas * settings.cutoffSigmas));
    glUniform1f(glGetUniformLocation(nearLayerProgram, "uPeak"),
                float(kernelPeak(spacing, sigma, settings.cutoffSigmas)));
    glUniform1i(glGetUniformLocation(nearLayerProgram, "uXRay"), f.xray);
    glBindVertexArray(emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    nearDrawn = true;
}

void SplatRenderer::Gl::readNearCounters(SplatCounters& out) const {
    GLuint count = 0;
    if (nearDrawn) glGetNamedBufferSubData(nearBuffer, 0, sizeof count, &count);
    out.nearLayer = std::min<uint64_t>(count, uint64_t(kMaxNearKernels));
    out.droppedNear = count - out.nearLayer;
}

} // namespace renderer
