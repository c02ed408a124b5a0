// Image-aligned slabs' pixel work on the GPU (see image_slabs_gl.h).
#include "renderer/gl/image_slabs_gl.h"

#include "gl_util.h"
#include "shader_sources.h"
#include "splat_renderer_state.h"

#include "renderer/errors.h"
#include "renderer/oracle/near_layer.h"
#include "renderer/oracle/pixel_filter.h"
#include "renderer/oracle/slab_setup.h"

#include <algorithm>
#include <utility>
#include <string>

namespace renderer {

namespace {

constexpr int kTilePx = 8;   // the shader's local size and tile side
constexpr int kInterruptBandTiles = 8;   // tile rows a dispatch covers when a newer view may cancel the frame

// Each kernel as the shader reads it (slab_composite.comp's Kernel, std430).
struct GpuKernel {
    glm::vec4 a, b;
    glm::vec2 slope;
    int32_t first, count;
    glm::vec4 adds, gradient;
};
static_assert(sizeof(GpuKernel) == 80);

std::vector<GpuKernel> packKernels(const SlabSetup& setup) {
    std::vector<GpuKernel> out;
    out.reserve(setup.splats.size());
    for (const SlabSplat& s : setup.splats) {
        const SplatGeometry& g = s.geometry;
        GpuKernel& k = out.emplace_back();
        k.a = glm::vec4(g.centrePx.x, g.centrePx.y, g.conic[0][0], 0.5 * (g.conic[0][1] + g.conic[1][0]));
        // Depth relative to the kernel's first slab: float keeps its fraction however far the volume is.
        k.b = glm::vec4(g.conic[1][1], g.amplitude, s.depth - double(s.first), s.depthSd);
        k.slope = glm::vec2(s.depthSlope);
        k.first = int32_t(s.first - setup.front);
        k.count = int32_t(s.last - s.first + 1);
        k.adds = setup.post ? glm::vec4(s.value, s.gradientCamera) : glm::vec4(glm::vec3(s.colour), 0.0f);
        k.gradient = glm::vec4(glm::vec3(s.gradientCamera), 0.0f);
    }
    return out;
}

// The kernels each 8x8 tile's pixels may take, in slab order: starts (tiles + 1) and the lists.
void listTiles(const SlabSetup& setup, int width, int height, std::vector<uint32_t>& starts,
               std::vector<uint32_t>& lists) {
    const int tilesX = (width + kTilePx - 1) / kTilePx, tilesY = (height + kTilePx - 1) / kTilePx;
    starts.assign(size_t(tilesX) * tilesY + 1, 0);
    const auto eachTile = [&](const SplatGeometry& g, auto&& fn) {
        const auto [xa, xb, ya, yb] = footprintBox(g, 0, height, width);
        if (xa > xb || ya > yb) return;
        for (int ty = ya / kTilePx; ty <= yb / kTilePx; ++ty)
            for (int tx = xa / kTilePx; tx <= xb / kTilePx; ++tx) fn(size_t(ty) * tilesX + tx);
    };
    for (const SlabSplat& s : setup.splats) eachTile(s.geometry, [&](size_t t) { ++starts[t + 1]; });
    for (size_t t = 1; t < starts.size(); ++t) starts[t] += starts[t - 1];
    lists.resize(std::max<size_t>(starts.back(), 1));
    std::vector<uint32_t> fill(starts.begin(), starts.end() - 1);
    for (uint32_t k = 0; k < uint32_t(setup.splats.size()); ++k)
        eachTile(setup.splats[k].geometry, [&](size_t t) { lists[fill[t]++] = k; });
}

// An immutable shader storage buffer holding `bytes` (at least 16: GL refuses empty storage).
GLuint storage(const void* data, size_t bytes, GLbitfield flags = 0) {
    GLuint b = 0;
    glCreateBuffers(1, &b);
    std::vector<char> zeros;
    if (bytes < 16) zeros.assign(16, 0), data = zeros.data(), bytes = 16;
    glNamedBufferStorage(b, GLsizeiptr(bytes), data, flags);
    return b;
}

} // namespace

ImageSlabsGl::ImageSlabsGl() {
    m_loopLimit = measureLoopLimit();
    m_program =
        gl::buildComputeProgram("slab_composite", programSource("slab_composite", "", "slab_composite.comp").c_str());
}

ImageSlabsGl::~ImageSlabsGl() { glDeleteProgram(m_program); }

Image ImageSlabsGl::renderPlane(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                                const SlabOptions& options, SlabCounters* counters) const {
    const SlabSetup setup = prepareSlabs(scene, plane, settings, options, m_interrupt);
    const int w = plane.width, h = plane.height;
    const double ringBytes = double(w) * h * double(setup.ring) * 5 * sizeof(float);
    if (ringBytes > kGlSlabRingBudget)
        throw RenderError("image-aligned slabs (GL): a kernel spans " + std::to_string(setup.ring) + " slabs of " +
                          std::to_string(options.thickness) + " voxels, " + std::to_string(int(ringBytes / 1048576)) +
                          " MiB of open slabs at " + std::to_string(w) + "x" + std::to_string(h) + " (at most " +
                          std::to_string(int(kGlSlabRingBudget / 1048576)) + " MiB): take thicker slabs");
    const std::vector<GpuKernel> kernels = packKernels(setup);
    std::vector<uint32_t> starts, lists;
    listTiles(setup, w, h, starts, lists);

    struct Buffers {   // deleted however the frame ends (a newer view cancels it between dispatches)
        GLuint ids[7];
        ~Buffers() {
            for (GLuint i = 0; i < 7; ++i) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, 0);
            glUseProgram(0);
            glDeleteBuffers(7, ids);
        }
    } owned{{
        storage(kernels.data(), kernels.size() * sizeof(GpuKernel)),
        storage(starts.data(), starts.size() * sizeof(uint32_t)),
        storage(lists.data(), lists.size() * sizeof(uint32_t)),
        storage(scene.lut.data(), scene.lut.size() * sizeof(glm::vec4)),
        storage(nullptr, size_t(w) * h * sizeof(glm::vec4)),
        storage(nullptr, size_t(w) * h * sizeof(glm::uvec4)),
        storage(nullptr, size_t(ringBytes)),
    }};
    const GLuint* buffers = owned.ids;
    const GLuint program = m_program;
    glUseProgram(program);
    const auto at = [&](const char* name) { return glGetUniformLocation(program, name); };
    glUniform2i(at("uSize"), w, h);
    glUniform1i(at("uTilesX"), (w + kTilePx - 1) / kTilePx);
    glUniform1i(at("uRing"), int(setup.ring));
    glUniform1i(at("uStride"), setup.stride);
    glUniform1i(at("uLutSize"), int(scene.lut.size()));
    glUniform1f(at("uCut2"), float(settings.cutoffSigmas * settings.cutoffSigmas));
    glUniform1f(at("uOpaqueAlpha"), float(settings.opaqueAlpha));
    glUniform1f(at("uPerOpacity"), float(setup.perOpacity));
    glUniform1f(at("uFPx"), float(plane.fPx));
    glUniform2f(at("uCentrePx"), float(plane.centrePx.x), float(plane.centrePx.y));
    glUniform1i(at("uPost"), setup.post);
    glUniform1i(at("uShaded"), setup.shaded);
    glUniform1i(at("uPerFragment"), setup.perFragment);
    glUniform1i(at("uOrtho"), plane.orthographic);
    setShadingUniforms(program, settings.shadingParams);
    for (GLuint i = 0; i < 7; ++i) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, buffers[i]);
    // Entries a dispatch may take under the driver's loop limit: a kernel costs at most one iteration,
    // `ring` to composite the slabs before it and `ring` for its shares; starting and finishing a pixel
    // cost 5 ring and ring more.
    uint32_t busiest = 0;
    for (size_t t = 0; t + 1 < starts.size(); ++t) busiest = std::max(busiest, starts[t + 1] - starts[t]);
    const uint32_t ring = uint32_t(setup.ring);
    const uint32_t perDispatch =
        m_loopLimit == 0 ? std::max<uint32_t>(busiest, 1)
                         : std::max<uint32_t>(1, (m_loopLimit - std::min(m_loopLimit, 6 * ring + 64)) / (2 * ring + 1));
    for (uint32_t e0 = 0; e0 == 0 || e0 < busiest; e0 += perDispatch) {
        glUniform1ui(at("uEntry0"), e0);
        glUniform1ui(at("uEntry1"), e0 + perDispatch);
        glUniform1i(at("uFirst"), e0 == 0);
        glUniform1i(at("uLast"), e0 + perDispatch >= busiest);
        // With an interrupt, in bands of tile rows, each waited for before the question: a post-classified
        // dispatch over the whole image took seconds on llvmpipe, a newer view's wait.
        const int tilesY = (h + kTilePx - 1) / kTilePx, band = m_interrupt ? kInterruptBandTiles : tilesY;
        for (int row0 = 0; row0 < tilesY; row0 += band) {
            glUniform1i(at("uTileRow0"), row0);
            glDispatchCompute(GLuint((w + kTilePx - 1) / kTilePx), GLuint(std::min(band, tilesY - row0)), 1);
            if (!m_interrupt) continue;
            glFinish();   // so that the question comes after the band's work, not after its queueing
            if (m_interrupt()) throw Cancelled("image-aligned slabs (GL): superseded");
        }
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }

    std::vector<glm::vec4> pixels(size_t(w) * h);
    std::vector<glm::uvec4> work(size_t(w) * h);
    glGetNamedBufferSubData(buffers[4], 0, GLsizeiptr(pixels.size() * sizeof(glm::vec4)), pixels.data());
    glGetNamedBufferSubData(buffers[5], 0, GLsizeiptr(work.size() * sizeof(glm::uvec4)), work.data());

    std::vector<double> acc(size_t(w) * h * 4);
    for (size_t i = 0; i < pixels.size(); ++i)
        for (int c = 0; c < 4; ++c) acc[4 * i + size_t(c)] = pixels[i][c];
    if (counters) {
        *counters = setup.counters;
        for (const glm::uvec4& n : work) counters->footprintPixels += n.y, counters->slabWrites += n.z;
    }
    return imageWithNearLayer(scene, plane, settings, setup.near, std::move(acc));
}

Image ImageSlabsGl::render(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                           const SlabOptions& options, SlabCounters* counters) const {
    requireSlabSupersample(options.supersample);
    return renderSupersampled(plane, options.supersample, [&](const ImagePlane& p) {
        return renderPlane(scene, p, settings, options, counters);
    });
}

} // namespace renderer
