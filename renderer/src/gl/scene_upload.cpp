// Getting a scene onto the GPU: setScene, setGradients and setLut, the view's axis made resident, and the
// memory checks that turn GL_OUT_OF_MEMORY into a RenderError saying how much the scene needs.
#include "splat_renderer_state.h"

#include "renderer/out_of_memory.h"

#include <algorithm>

namespace renderer {

namespace {

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
    if (takeOutOfMemory(std::string("SplatRenderer::setScene ") + what))
        throw RenderError(
            memoryMessage(name, needed, freeBytes, std::string(" (GL_OUT_OF_MEMORY allocating the ") + what + ")"));
}

// One axis's lists as the GPU reads them (host side: Gl::makeResident uploads them).
AxisBuffers hostAxis(const AxisLists& lists) {
    AxisBuffers a;
    const size_t n = lists.runs.size();
    a.hostEntries = lists.sharedEntries;
    a.hostRuns.assign(std::max<size_t>(n, 1), glm::uvec4(0));
    a.buckets.resize(n);
    a.voxels.resize(n);
    a.lo.resize(n);
    a.hi.resize(n);
    a.sliceRuns = lists.sliceRuns;
    for (size_t r = 0; r < n; ++r) {
        const SliceRun& run = lists.runs[r];
        a.hostRuns[r] = glm::uvec4(run.dense ? 0u : run.first, run.tileBase,
                                   run.slice | uint32_t(run.bucket) << 16 | (run.dense ? 1u << 31 : 0u), run.count);
        a.buckets[r] = run.bucket;
        a.voxels[r] = run.voxels;
        a.lo[r] = run.lo;
        a.hi[r] = run.hi;
    }
    a.runCount = uint32_t(n);
    return a;
}

} // namespace

void SplatRenderer::setScene(const SplatScene& scene) {
    Gl& g = *m_gl;
    const glm::ivec3 d = scene.dims;
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &maxSize);
    if (d.x > maxSize || d.y > maxSize || d.z > maxSize)
        throw RenderError("volume dims exceed GL_MAX_3D_TEXTURE_SIZE " + std::to_string(maxSize));
    // GPU memory: the classes (2 bytes a voxel), the LUT, the lists of the view's axis (the largest
    // counts): entries (2 bytes each), runs (16 bytes) and where each slice's runs start (4 bytes a
    // slice), and one command array (16 bytes a run of the axis with the most), against what the driver
    // reports free (plus what the current scene holds, which is replaced) and the optional limit.
    std::array<AxisBuffers, 3> axes;   // host side only until the check passes
    uint64_t listBytes = 0;
    size_t mostRuns = 1;
    // The host copies of the three axes' runs, kept to upload an axis when the view turns to it (the
    // entries, most of the lists, are the scene's own, shared).
    uint64_t hostBytes = 0;
    for (const AxisLists& lists : scene.lists)
        hostBytes += lists.sliceRuns.size() * 4 +
                     lists.runs.size() * (sizeof(glm::uvec4) + 2 + 4 + 2 * sizeof(glm::u16vec2));
    namingAllocation(volumeSubject(scene.name), "copies of the slice lists for the GPU", hostBytes, "", [&] {
        for (int axis = 0; axis < 3; ++axis) axes[size_t(axis)] = hostAxis(scene.lists[size_t(axis)]);
    });
    for (const AxisBuffers& a : axes) {
        listBytes = std::max(listBytes, a.gpuBytes());
        mostRuns = std::max(mostRuns, a.hostRuns.size());
    }
    const uint64_t commandBytes = mostRuns * 32;   // both layouts (bucket_commands.comp)
    if (!g.lutBuffer) g.lutBufferEntries = kTf2dFirstEntry;   // the 2D TF's cells come with the first 2D TF
    uint64_t needed = scene.classes.size() * sizeof(uint16_t) + g.lutBufferEntries * sizeof(glm::vec4) + listBytes +
                      commandBytes + gradientBufferBytes(scene.gradients.size());
    std::optional<uint64_t> freeBytes = freeGpuMemoryBytes();
    if (freeBytes) *freeBytes += g.sceneBytes;
    if (g.memoryLimit) freeBytes = std::min(freeBytes.value_or(g.memoryLimit), g.memoryLimit);
    if (freeBytes && needed > *freeBytes) throw RenderError(memoryMessage(scene.name, needed, freeBytes, ""));
    checkGlErrors("SplatRenderer::setScene (before uploading)");

    m_stats.uploadBytes = 0;
    if (g.dims != d) g.releaseWorkingBuffers();
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

    if (!g.lutBuffer) {
        g.createLutBuffer(g.lutBufferEntries);
        checkAllocation("LUT buffer", scene.name, needed, freeBytes);
    }
    g.sceneBytes = scene.classes.size() * sizeof(uint16_t) + g.lutBufferEntries * sizeof(glm::vec4);

    for (int axis = 0; axis < 3; ++axis) {
        g.axes[size_t(axis)].release();
        g.axes[size_t(axis)] = std::move(axes[size_t(axis)]);
    }
    g.residentAxis = -1;   // the first frame uploads its axis's lists
    g.sceneBytes += listBytes + commandBytes;
    g.sceneName = scene.name;
    glDeleteBuffers(1, &g.commands);
    glCreateBuffers(1, &g.commands);
    glNamedBufferStorage(g.commands, GLsizeiptr(commandBytes), nullptr, 0);
    checkAllocation("draw commands", scene.name, needed, freeBytes);
    g.commandsKey = {};   // other runs: written afresh
    g.dims = d;
    g.patchLayout.reset();   // another scene: no last frame to keep filters from
    g.origin = scene.origin;
    g.spacing = scene.spacing;
    const uint64_t sceneUpload = m_stats.uploadBytes;
    g.uploadedSinceFrame += sceneUpload;   // setGradients and setLut add theirs
    g.gradientBytes = 0;   // counted afresh in sceneBytes by setGradients
    setGradients(scene);
    const uint64_t gradientUpload = m_stats.uploadBytes;
    setLut(tfTables(scene));
    m_stats.uploadBytes += sceneUpload + gradientUpload;
    checkGlErrors("SplatRenderer::setScene");
}

void SplatRenderer::setGradients(const SplatScene& scene) {
    Gl& g = *m_gl;
    if (!g.classTexture || scene.dims != g.dims)
        throw RenderError("SplatRenderer::setGradients: call setScene with scene '" + scene.name + "' first");
    // Packed gradients, 3 bytes a voxel, when the scene has them (one word otherwise: a valid binding).
    const size_t bytes = gradientBufferBytes(scene.gradients.size());
    std::vector<uint8_t> packed = namingAllocation(volumeSubject(scene.name), "packed gradients for the GPU", bytes,
                                                   "", [&] { return std::vector<uint8_t>(bytes, 0); });
    for (size_t v = 0; v < scene.gradients.size(); ++v)
        for (size_t k = 0; k < 3; ++k) packed[3 * v + k] = uint8_t(scene.gradients[v] >> (8 * k));
    glDeleteBuffers(1, &g.gradientBuffer);
    glCreateBuffers(1, &g.gradientBuffer);
    glNamedBufferStorage(g.gradientBuffer, GLsizeiptr(bytes), packed.data(), 0);
    checkAllocation("gradients", scene.name, bytes, freeGpuMemoryBytes());
    g.sceneBytes += bytes - g.gradientBytes;
    g.gradientBytes = bytes;
    // Against the grid's voxels, not scene.classes: a scene holding only name, dims and gradients will do.
    g.hasGradients = scene.gradients.size() == size_t(g.dims.x) * size_t(g.dims.y) * size_t(g.dims.z);
    m_stats.uploadBytes = bytes;
    g.uploadedSinceFrame += bytes;
}

void SplatRenderer::Gl::createLutBuffer(size_t entries) {
    glDeleteTextures(1, &lutTexture);
    glDeleteTextures(1, &tf2dTexture);
    glDeleteBuffers(1, &lutBuffer);
    tf2dTexture = 0;
    glCreateBuffers(1, &lutBuffer);
    glNamedBufferStorage(lutBuffer, GLsizeiptr(entries * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &lutTexture);
    glTextureBuffer(lutTexture, GL_RGBA32F, lutBuffer);
    if (entries >= kLutBufferEntries) {   // a view of the cells for the tiles' composite
        glCreateTextures(GL_TEXTURE_BUFFER, 1, &tf2dTexture);
        glTextureBufferRange(tf2dTexture, GL_RGBA32F, lutBuffer, GLintptr(kTf2dFirstEntry * sizeof(glm::vec4)),
                             GLsizeiptr(size_t(kTf2dCells) * sizeof(glm::vec4)));
    }
    lutBufferEntries = entries;
}

void SplatRenderer::setLut(const TfTables& tables) {
    Gl& g = *m_gl;
    const Lut& lut = tables.lut;
    const GradientFactors& gradientFactors = tables.gradientFactors;
    if (lut.size() != size_t(kLutSize)) throw RenderError("LUT must have " + std::to_string(kLutSize) + " entries");
    if (!gradientFactors.empty() && gradientFactors.size() != size_t(kGradientBins))
        throw RenderError("gradient factors must have " + std::to_string(kGradientBins) + " entries");
    if (!tables.tf2d.empty() && tables.tf2d.size() != size_t(kTf2dCells))
        throw RenderError("a 2D transfer function table must have " + std::to_string(kTf2dCells) + " entries");
    if (!g.lutBuffer) throw RenderError("SplatRenderer::setLut called before setScene");
    if (!tables.tf2d.empty() && g.lutBufferEntries < kLutBufferEntries) {
        // The first 2D TF: a buffer with room for its cells (256 KiB more), the LUT uploaded into it below.
        g.sceneBytes += (kLutBufferEntries - g.lutBufferEntries) * sizeof(glm::vec4);
        g.createLutBuffer(kLutBufferEntries);
    }
    glNamedBufferSubData(g.lutBuffer, 0, GLsizeiptr(lut.size() * sizeof(glm::vec4)), lut.data());
    m_stats.uploadBytes = lut.size() * sizeof(glm::vec4);
    // The factors after the LUT's entries, a texel each (splat_footprint.glsl reads .a).
    if (!gradientFactors.empty()) {
        std::vector<glm::vec4> texels(gradientFactors.begin(), gradientFactors.end());
        glNamedBufferSubData(g.lutBuffer, GLintptr(kLutSize * sizeof(glm::vec4)),
                             GLsizeiptr(texels.size() * sizeof(glm::vec4)), texels.data());
        m_stats.uploadBytes += texels.size() * sizeof(glm::vec4);
    }
    if (!tables.tf2d.empty()) {   // the cells after the factors (splat_footprint.glsl's TF_2D)
        glNamedBufferSubData(g.lutBuffer, GLintptr(kTf2dFirstEntry * sizeof(glm::vec4)),
                             GLsizeiptr(tables.tf2d.size() * sizeof(glm::vec4)), tables.tf2d.data());
        m_stats.uploadBytes += tables.tf2d.size() * sizeof(glm::vec4);
    }
    g.gradientOpacity = !gradientFactors.empty();
    g.tf2d = !tables.tf2d.empty();
    g.lut = lut;
    ++g.lutVersion;
    g.uploadedSinceFrame += m_stats.uploadBytes;
    checkGlErrors("SplatRenderer::setLut");
}

// Puts the lists of `axis` on the GPU in place of the resident axis's, so a scene holds one axis,
// not three (sceneBytes counts the largest). Returns the bytes uploaded: 0 while the view's major
// axis stays the same.
uint64_t SplatRenderer::Gl::makeResident(int axis) {
    if (residentAxis == axis) return 0;
    if (residentAxis >= 0) axes[size_t(residentAxis)].release();
    residentAxis = -1;
    AxisBuffers& a = axes[size_t(axis)];
    const std::optional<uint64_t> freeBytes = freeGpuMemoryBytes();
    // `bytes` of storage, the first `dataBytes` of it from `data` (the entries' last word may be half used).
    auto uploadPart = [&](GLuint& buffer, size_t bytes, const void* data, size_t dataBytes) {
        glCreateBuffers(1, &buffer);
        glNamedBufferStorage(buffer, GLsizeiptr(bytes), dataBytes == bytes ? data : nullptr,
                             dataBytes == bytes ? 0 : GL_DYNAMIC_STORAGE_BIT);
        checkAllocation("slice lists", sceneName, sceneBytes, freeBytes);
        if (dataBytes != bytes && dataBytes > 0) glNamedBufferSubData(buffer, 0, GLsizeiptr(dataBytes), data);
    };
    auto upload = [&](GLuint& buffer, size_t bytes, const void* data) { uploadPart(buffer, bytes, data, bytes); };
    try {
        const size_t entryDataBytes = a.hostEntries ? a.hostEntries->size() * 2 : 0;
        uploadPart(a.entries, a.entryBytes(), entryDataBytes ? a.hostEntries->data() : nullptr, entryDataBytes);
        upload(a.runs, a.hostRuns.size() * sizeof(glm::uvec4), a.hostRuns.data());
        upload(a.sliceRunsBuffer, a.sliceRuns.size() * 4, a.sliceRuns.data());
    } catch (...) {
        a.release();
        throw;
    }
    residentAxis = axis;
    return a.gpuBytes();
}

} // namespace renderer
