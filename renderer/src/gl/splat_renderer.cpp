// The GL splatting path (see splat_renderer.h). Rasterised: one point (or 6 vertices) per splat; the
// vertex stage fetches the voxel index from the visible list, rebuilds the footprint exactly as
// splatGeometry() does on the CPU (same formulas, float instead of double) and emits a point or quad
// around the cutoff ellipse; the fragment stage evaluates the Gaussian at the pixel centre. Tiled
// (sheets and X-ray): compute passes build the same footprints, bin them to screen tiles and
// composite each tile's pixels in registers (renderer/shaders/tile_*.comp).
#include "renderer/gl/splat_renderer.h"

#include "gl_util.h"
#include "gl/shader_sources.h"
#include "renderer/math/classifier.h"
#include "renderer/errors.h"
#include "renderer/gl/gl_context.h"
#include "renderer/math/shading.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>

namespace renderer {

namespace {

// The #define of the programs that share the opaque-tile size.
std::string opaqueTileDefine() { return "#define OPAQUE_TILE " + std::to_string(kOpaqueTilePx) + "\n"; }

constexpr int kTimerRing = 4;
// Tiled splatting culls against the opaque-tile map with its own tile indices.
static_assert(kOpaqueTilePx == kSplatTilePx);
// Texels a chunk of several slices may give its lists (256 MiB at 16 bytes a texel); more, and the
// chunk goes in parts. One slice cannot be split (its sheet is one sum), so only the driver's
// GL_MAX_TEXTURE_BUFFER_SIZE bounds it.
constexpr uint64_t kTileListBudgetTexels = uint64_t(1) << 24;
// Where the driver ends a shader's loops after a number of iterations, all loops together (llvmpipe:
// 65535, Gl::loopLimit), the composite's loops beyond the busiest tile's entries and the ranks' stay
// under this; a chunk whose busiest tile needs more goes in parts.
constexpr uint64_t kCompositeLoopSlack = 64;
// The most workgroups the record pass deals one run to when that limit cuts a run short.
constexpr GLuint kMaxRunSegments = 4096;

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

// Counter slots of the vertex stage's count(): the SplatCounters fields in this order.
enum CounterSlot { kVisible, kTransparent, kNear, kDegenerate, kHuge, kOffscreen, kDrawn, kMode0, kOccluded = kMode0 + 3,
                   kCounterSlots };

// One traversal axis: the 16-bit entries, the runs (the vertex stage's per-draw attribute) and where
// each slice's runs start (the command pass's descending order). Only the view's axis is on the GPU
// (Gl::makeResident); the others wait in host memory, as uploaded. The CPU keeps the run buckets and
// slice ranges to skip empty slices.
struct AxisBuffers {
    GLuint entries = 0, runs = 0, sliceRunsBuffer = 0;   // 0 while the axis is not resident
    uint32_t runCount = 0;
    std::vector<uint32_t> sliceRuns;   // as AxisLists::sliceRuns
    std::vector<uint16_t> buckets;     // per run
    std::vector<uint32_t> voxels;      // per run: voxels of its bucket
    std::vector<glm::u16vec2> lo, hi;  // per run: in-slice bounds of its voxels
    std::vector<uint16_t> hostEntries; // the entries in whole words (never empty: zero-sized stores are errors)
    std::vector<glm::uvec4> hostRuns;  // the runs as the GPU reads them (at least one)

    uint64_t gpuBytes() const {
        return hostEntries.size() * 2 + hostRuns.size() * sizeof(glm::uvec4) + sliceRuns.size() * 4;
    }
    void release() {
        const GLuint b[] = {entries, runs, sliceRunsBuffer};
        glDeleteBuffers(3, b);
        entries = runs = sliceRunsBuffer = 0;
    }
};

} // namespace

// Feature bits of a splat program variant: #defines of renderer/shaders/ (every set: programs.cmake).
enum SplatVariant { kCounters = 1, kSurface = 2, kSplatShading = 4, kFragmentShading = 8, kHeatmap = 16, kAdaptive = 32,
                    kOcclusion = 64 };

// Tiled splatting's vec4s per splat record and per list entry (tile_record.comp, tile_scatter.comp).
int recordVec4s(int bits) { return bits & kFragmentShading ? 4 : 3; }
int entryTexels(int bits) { return bits & (kSplatShading | kFragmentShading) ? 3 : 2; }

// The #defines of a variant's features.
std::string variantDefines(int bits) {
    const std::pair<int, const char*> defines[] = {{kCounters, "COUNTERS"}, {kSurface, "SURFACE"},
                                                   {kSplatShading, "SPLAT_SHADING"},
                                                   {kFragmentShading, "FRAGMENT_SHADING"}, {kHeatmap, "HEATMAP"},
                                                   {kAdaptive, "ADAPTIVE"}, {kOcclusion, "OCCLUSION"}};
    std::string header;
    for (auto [bit, name] : defines)
        if (bits & bit) header += std::string("#define ") + name + "\n";
    return header;
}

// Whether the tile composite may take the Gaussian down a column by recurrence (COLUMN_RECURRENCE): every
// footprint holds the 1-px low-pass (its conic's entries are at most 1) and the cutoff is at most 3 sigmas.
// Both bound its products (tile_composite.comp).
bool columnRecurrence(FilterMode drawn, glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing, const ImagePlane& plane,
                      const SplatSettings& s) {
    return s.cutoffSigmas <= 3.0 && footprintsHoldThePixel(drawn, dims, origin, spacing, plane, s);
}

struct SplatRenderer::Gl {
    std::map<int, GLuint> splatPrograms;   // by SplatVariant bits, built on first use
    std::array<GLuint, 2> compositePrograms{};   // without and with the heatmap
    GLuint opaqueMaskProgram = 0, resolveProgram = 0, displayProgram = 0;
    GLuint commandsProgram = 0, patchProgram = 0, opaqueTilesProgram = 0;
    GLuint splatVao = 0, emptyVao = 0;
    GLuint classTexture = 0;
    GLuint lutBuffer = 0, counterBuffer = 0, gradientBuffer = 0;
    GLuint patchTexture = 0;   // R8UI, a texel a patch (PatchGrid: columns x rows x slices)
    GLuint lutTexture = 0;   // buffer texture over lutBuffer (the tiles' composite)
    bool hasGradients = false;
    uint64_t gradientBytes = 0;   // of gradientBuffer, inside sceneBytes
    std::string sceneName;   // for messages
    glm::ivec3 patchTextureSize{0};
    std::optional<PatchGrid> patchLayout;   // patchTexture holds an adaptive frame's modes on this
                                            // grid (hysteresis reads them as last frame's)
    std::array<AxisBuffers, 3> axes;
    int residentAxis = -1;   // the axis whose lists are on the GPU (-1: none yet)
    Lut lut;                             // CPU copy: which buckets are active, which slices are empty
    // The one indirect command array (both layouts: 32 bytes a run of the longest axis), rewritten when
    // the LUT, drawAllBuckets, the axis or the order changes.
    GLuint commands = 0;
    uint64_t lutVersion = 1;
    struct CommandsKey {
        uint64_t lutVersion = 0;
        int axis = -1;
        bool allBuckets = false, descending = false, reversed = false;
        bool operator==(const CommandsKey&) const = default;
    } commandsKey;
    // Targets: the frame's image and heatmap, the slice sheets, and a depth buffer both FBOs share
    // (front-to-back early termination).
    GLuint image = 0, heat = 0, sheet = 0, sheetHeat = 0, depth = 0, displayTex = 0;
    GLuint frameFbo = 0, sheetFbo = 0, displayFbo = 0, depthFbo = 0;
    GLuint computeFbo = 0;   // no attachments: bound while a tiled frame runs its compute passes
    GLuint opaqueTiles = 0;   // one word per kOpaqueTilePx tile: 1 once all its pixels are opaque; then
                              // one word, 1 once any is (nextOcclusionChunk())
    // Tiled splatting: programs by variant bits, and its per-frame buffers (grown, never shrunk).
    std::map<int, GLuint> tilePrograms;
    GLuint tileSplats = 0, tileBins = 0, tileState = 0, tileList = 0, tileBusy = 0;
    GLuint tileListTexture = 0;   // buffer texture over tileList
    GLuint tileSplatTexture = 0;  // buffer texture over tileSplats
    GLuint tileStateTexture = 0;  // buffer texture over tileState (the scatter's tile bases)
    GLuint opaqueTexture = 0;     // buffer texture over the map splats are culled against
    size_t tileSplatBytes = 0, tileBinBytes = 0, tileStateBytes = 0, tileListBytes = 0, tileBusyBytes = 0;
    // A chunk split to fit its lists: the opaque-tile map at its start, which its parts cull against,
    // and the counters before a part that did not fit (it goes again smaller).
    GLuint chunkStartMap = 0, savedCounters = 0;
    size_t chunkStartMapBytes = 0, savedCounterBytes = 0;
    glm::ivec2 tiles{0};
    int width = 0, height = 0;
    // Per ring slot, a timed frame's laps: GL_TIMESTAMP queries where it starts, where each pass starts
    // and where it ends (grown as frames need them, kept). Timestamps, not a GL_TIME_ELAPSED query:
    // llvmpipe starts that at the first draw, so a frame of compute passes (tiles) read its clock.
    struct Laps {
        std::vector<GLuint> queries;
        std::vector<std::optional<GpuPass>> passes;   // what runs from each query to the next
        size_t used = 0;
    };
    std::array<Laps, kTimerRing> laps;
    Laps* timing = nullptr;            // the frame being timed; null outside a timed frame
    std::optional<GpuPass> lapPass;    // the pass its last lap started
    std::array<bool, kTimerRing> timerPending{};
    std::array<uint64_t, kTimerRing> timerFrame{};
    std::array<int, kTimerRing> timerFirstUses{};   // the timed frame's FrameStats::firstUsePrograms
    // Programs used so far, and those the frame being issued used first: drivers compile (llvmpipe: JIT)
    // a program at its first draw or dispatch, and that time lands in the frame.
    std::set<GLuint> usedPrograms;
    int firstUses = 0;
    void useProgram(GLuint p) {
        glUseProgram(p);
        if (usedPrograms.insert(p).second) ++firstUses;
    }
    uint64_t renders = 0, newestTimed = 0;   // render numbers (FrameStats::frame)
    int timerNext = 0;
    GLint maxPointSize = 1;
    GLint maxTexelBuffer = 0;   // GL_MAX_TEXTURE_BUFFER_SIZE: tiled splatting reads records through it
    uint64_t texelLimit = 0;    // setTexelBufferLimit(); 0: none
    uint64_t texelCap() const {
        return texelLimit ? std::min<uint64_t>(texelLimit, uint64_t(maxTexelBuffer)) : uint64_t(maxTexelBuffer);
    }
    // Invocations a run of voxels takes in the record pass. llvmpipe: one SIMD row (8 lanes of 256
    // bits) looping over the run, 5 % faster on bonsai than 64 (fewer idle rows, each started once);
    // a GPU keeps full warps.
    int runLanes = 64;
    // Slices tiled splatting bins at once where nothing is culled (back to front, X-ray, no early
    // termination). A GPU waits for each chunk's read-back, so it takes 64 (bonsai back to front: 126 MB
    // for its largest chunk against 255 MB for all slices at once, at the same speed). llvmpipe: 16,
    // whose smaller lists stay in cache: bonsai and engine 3-5 % faster than 64, headsq 2-14 %.
    uint32_t listChunkSlices = 64;
    uint32_t listChunkSlicesSet = 0;   // setListChunkSlices(); 0: listChunkSlices
    // Loop iterations the driver lets one shader invocation run, all its loops together (llvmpipe
    // ends them at 65535; measured at start by measureLoopLimit()); 0: no limit found.
    uint32_t loopLimit = 0;
    GLuint fragmentQuery = 0;   // GL_SAMPLES_PASSED of a counted frame
    // Scene constants the vertex stage needs.
    glm::ivec3 dims{0};
    glm::dvec3 origin{0.0}, spacing{1.0};
    uint64_t sceneBytes = 0;
    uint64_t uploadedSinceFrame = 0;   // by setScene, setGradients and setLut since the last render
    uint64_t memoryLimit = 0;   // setMemoryLimit(); 0: none beyond what the driver reports

    ~Gl() {
        for (auto [bits, p] : splatPrograms) glDeleteProgram(p);
        for (auto [bits, p] : tilePrograms) glDeleteProgram(p);
        const GLuint tileBuffers[] = {tileSplats, tileBins, tileState, tileList,
                                      tileBusy, chunkStartMap, savedCounters};
        glDeleteBuffers(7, tileBuffers);
        glDeleteTextures(1, &tileListTexture);
        glDeleteTextures(1, &tileSplatTexture);
        glDeleteTextures(1, &opaqueTexture);
        glDeleteTextures(1, &tileStateTexture);
        for (GLuint p : {compositePrograms[0], compositePrograms[1], opaqueMaskProgram, resolveProgram, displayProgram,
                         commandsProgram, patchProgram, opaqueTilesProgram})
            glDeleteProgram(p);
        glDeleteFramebuffers(1, &computeFbo);
        const GLuint vaos[] = {splatVao, emptyVao};
        glDeleteVertexArrays(2, vaos);
        glDeleteTextures(1, &classTexture);
        glDeleteTextures(1, &lutTexture);
        glDeleteTextures(1, &patchTexture);
        const GLuint buffers[] = {lutBuffer, counterBuffer, gradientBuffer, commands};
        glDeleteBuffers(4, buffers);
        for (auto& a : axes) a.release();
        releaseTargets();
        for (Laps& l : laps) glDeleteQueries(GLsizei(l.queries.size()), l.queries.data());
        glDeleteQueries(1, &fragmentQuery);
    }

    void releaseTargets() {
        const GLuint textures[] = {image, heat, sheet, sheetHeat, depth, displayTex};
        const GLuint fbos[] = {frameFbo, sheetFbo, displayFbo, depthFbo};
        glDeleteTextures(6, textures);
        glDeleteFramebuffers(4, fbos);
        glDeleteBuffers(1, &opaqueTiles);
        image = heat = sheet = sheetHeat = depth = displayTex = frameFbo = sheetFbo = displayFbo = depthFbo = 0;
        opaqueTiles = 0;
    }

    static GLuint makeTexture(GLenum format, int w, int h) {
        GLuint texture = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &texture);
        glTextureStorage2D(texture, 1, format, w, h);
        glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        return texture;
    }

    static GLuint makeFbo(std::initializer_list<GLuint> colours, GLuint depthTexture) {
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

    void ensureTargets(int w, int h) {
        if (w == width && h == height && image) return;
        releaseTargets();
        image = makeTexture(GL_RGBA32F, w, h);
        heat = makeTexture(GL_RGBA32F, w, h);
        sheet = makeTexture(GL_RGBA32F, w, h);
        sheetHeat = makeTexture(GL_RGBA32F, w, h);
        depth = makeTexture(GL_DEPTH_COMPONENT32F, w, h);
        displayTex = makeTexture(GL_RGBA8, w, h);
        glTextureParameteri(displayTex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(displayTex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        frameFbo = makeFbo({image, heat}, depth);
        sheetFbo = makeFbo({sheet, sheetHeat}, depth);
        displayFbo = makeFbo({displayTex}, 0);
        depthFbo = makeFbo({}, depth);   // the opaque mask of splat-every-sample: reads the image
        tiles = glm::ivec2((w + kOpaqueTilePx - 1) / kOpaqueTilePx, (h + kOpaqueTilePx - 1) / kOpaqueTilePx);
        glCreateBuffers(1, &opaqueTiles);
        glNamedBufferStorage(opaqueTiles, GLsizeiptr(opaqueMapBytes()), nullptr, 0);
        width = w;
        height = h;
    }

    // Timestamps the start of `pass` in the frame being timed (nothing when the pass goes on); no pass:
    // the frame's start or end.
    void lap(std::optional<GpuPass> pass) {
        if (!timing || (pass && pass == lapPass)) return;
        Laps& l = *timing;
        if (l.used == l.queries.size()) {
            GLuint q = 0;
            glCreateQueries(GL_TIMESTAMP, 1, &q);
            l.queries.push_back(q);
            l.passes.emplace_back();
        }
        glQueryCounter(l.queries[l.used], GL_TIMESTAMP);
        l.passes[l.used++] = pass;
        lapPass = pass;
    }

    // X-ray's sums become 1 - exp(-sum), in place (xray_resolve.frag).
    void resolveXRay(int w, int h) {
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

    // Whether any tile of the opaque-tile map is opaque (a wait for the passes before it).
    bool anyTileOpaque() {
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        GLuint flag = 0;
        glGetNamedBufferSubData(opaqueTiles, GLintptr(size_t(tiles.x) * size_t(tiles.y) * 4), 4, &flag);
        return flag != 0;
    }

    // The opaque-tile map (binding 11) from the image's alpha: what occlusion culling reads.
    void updateOpaqueTiles(float opaqueAlpha) {
        useProgram(opaqueTilesProgram);
        glUniform1f(glGetUniformLocation(opaqueTilesProgram, "uOpaqueAlpha"), opaqueAlpha);
        glUniform2i(glGetUniformLocation(opaqueTilesProgram, "uTiles"), tiles.x, tiles.y);
        glBindTextureUnit(2, image);
        glDispatchCompute(GLuint((tiles.x + 7) / 8), GLuint((tiles.y + 7) / 8), 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    }

    // Binds to `unit` the buffer texture `texture` (created on first use) over the first `bytes` of
    // `buffer`: llvmpipe fetches texels lane by lane as a gather, storage-buffer values component by
    // component, so the passes read what they do not write as texels.
    static void bindTexels(GLuint& texture, GLenum format, GLuint buffer, GLsizeiptr bytes, GLuint unit) {
        if (!texture) glCreateTextures(GL_TEXTURE_BUFFER, 1, &texture);
        glTextureBufferRange(texture, format, buffer, 0, bytes);
        glBindTextureUnit(unit, texture);
    }

    // The opaque-tile map occlusion culling reads (opaque_tiles_read.glsl).
    void bindCullMap(GLuint map) {
        bindTexels(opaqueTexture, GL_R32UI, map, GLsizeiptr(opaqueMapBytes()), 7);
    }
    // The map: a word a tile, then one that says whether any tile is opaque.
    size_t opaqueMapBytes() const { return (size_t(tiles.x) * size_t(tiles.y) + 1) * 4; }

    GLuint splatProgram(int bits) {
        auto it = splatPrograms.find(bits);
        if (it != splatPrograms.end()) return it->second;
        const std::string defines = opaqueTileDefine() + variantDefines(bits);
        const GLuint p = gl::buildProgram("splat", programSource("splat", defines, "splat.vert").c_str(),
                                          programSource("splat", defines, "splat.frag").c_str());
        splatPrograms[bits] = p;
        return p;
    }

    // Tiled splatting's passes (renderer/shaders/tile_*.comp); bits: SplatVariant features of the splat and composite
    // passes.
    enum TilePass { kTileSplat = 1 << 8, kTileOffsets = 2 << 8, kTileBases = 3 << 8, kTileScatter = 4 << 8,
                    kTileComposite = 5 << 8, kTileXRay = 1 << 12, kTileColumnRecurrence = 1 << 13 };
    GLuint tileProgram(int pass, int bits) {
        const int key = pass | bits;
        auto it = tilePrograms.find(key);
        if (it != tilePrograms.end()) return it->second;
        std::string defines = opaqueTileDefine() + variantDefines(bits) + (bits & kTileXRay ? "#define XRAY\n" : "") +
                              (bits & kTileColumnRecurrence ? "#define COLUMN_RECURRENCE\n" : "") +
                              "#define SPLAT_TILE " + std::to_string(kSplatTilePx) + "\n#define BUSY_ROW 4096u\n" +
                              "#define RECORD_VEC4S " + std::to_string(recordVec4s(bits)) + "u\n#define ENTRY_TEXELS " +
                              std::to_string(entryTexels(bits)) + "u\n";
        if (pass == kTileSplat) defines += "#define RUN_LANES " + std::to_string(runLanes) + "\n";
        const char* program = pass == kTileSplat     ? "tile_record"
                              : pass == kTileOffsets ? "tile_offsets"
                              : pass == kTileBases   ? "tile_bases"
                              : pass == kTileScatter ? "tile_scatter"
                                                     : "tile_composite";
        const std::string source = programSource(program, defines, std::string(program) + ".comp");
        const GLuint p = gl::buildComputeProgram("tiled_splatting", source.c_str());
        tilePrograms[key] = p;
        return p;
    }

    // Grows `buffer` to at least `bytes` (with headroom); its contents are not kept.
    static void ensureBuffer(GLuint& buffer, size_t& capacity, size_t bytes) {
        if (bytes <= capacity && buffer) return;
        glDeleteBuffers(1, &buffer);
        capacity = std::max<size_t>(bytes + bytes / 4, 64);
        glCreateBuffers(1, &buffer);
        glNamedBufferStorage(buffer, GLsizeiptr(capacity), nullptr, 0);
    }

    // The adaptive classifier once per patch (compute) into patchTexture; returns the patch count. Where
    // uniformAdaptiveFilter() decided the view (`decided`, else Adaptive), every patch is set to that
    // filter, what the pass would give, so hysteresis reads it next frame.
    size_t classifyPatches(const ImagePlane& plane, const SplatSettings& settings, int axis,
                           FilterMode decided = FilterMode::Adaptive) {
        lap(GpuPass::Patches);
        const PatchGrid grid = patchGrid(dims, axis, settings.patchSize);
        const size_t n = grid.count();
        if (const glm::ivec3 size{grid.columns, grid.rows, grid.slices}; size != patchTextureSize) {
            glDeleteTextures(1, &patchTexture);
            glCreateTextures(GL_TEXTURE_3D, 1, &patchTexture);
            glTextureStorage3D(patchTexture, 1, GL_R8UI, size.x, size.y, size.z);
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
    void setCommonUniforms(GLuint p, const ImagePlane& plane, const SplatSettings& settings, int axis) const {
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

    // Puts the lists of `axis` on the GPU in place of the resident axis's, so a scene holds one axis,
    // not three (sceneBytes counts the largest). Returns the bytes uploaded: 0 while the view's major
    // axis stays the same.
    uint64_t makeResident(int axis) {
        if (residentAxis == axis) return 0;
        if (residentAxis >= 0) axes[size_t(residentAxis)].release();
        residentAxis = -1;
        AxisBuffers& a = axes[size_t(axis)];
        const std::optional<uint64_t> freeBytes = freeGpuMemoryBytes();
        auto upload = [&](GLuint& buffer, size_t bytes, const void* data) {
            glCreateBuffers(1, &buffer);
            glNamedBufferStorage(buffer, GLsizeiptr(bytes), data, 0);
            checkAllocation("slice lists", sceneName, sceneBytes, freeBytes);
        };
        try {
            upload(a.entries, a.hostEntries.size() * 2, a.hostEntries.data());
            upload(a.runs, a.hostRuns.size() * sizeof(glm::uvec4), a.hostRuns.data());
            upload(a.sliceRunsBuffer, a.sliceRuns.size() * 4, a.sliceRuns.data());
        } catch (...) {
            a.release();
            throw;
        }
        residentAxis = axis;
        return a.gpuBytes();
    }

    // Rewrites the indirect commands for the current LUT, axis and order (GPU only: nothing is
    // uploaded). Tiles read them ascending, by run.
    void updateCommands(int axis, bool descending, bool reversed, bool allBuckets) {
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
};

namespace {

// An upper bound on the cutoff half extent, in pixels, of any splat of slice `slice` across `axis`:
// ||J||^2 <= ||J||_F^2 = (f/u2)^2 (2 + (u0^2 + u1^2) / u2^2) + 1, with u2 at least its smallest value
// over the slice's corners (u2 is linear) and u0^2 + u1^2 at most its largest (convex). Infinite when
// the slice reaches the near plane. Close up, the near slices need quads where the far ones fit
// points, and their rasterised sheets reach further.
double sliceHalfExtentBound(const glm::ivec3& dims, const glm::dvec3& origin, const glm::dvec3& spacing,
                            const ImagePlane& plane, const SplatSettings& settings, int axis, int slice) {
    double u2min = std::numeric_limits<double>::infinity(), lateral2 = 0.0;
    for (int c = 0; c < 4; ++c) {
        glm::dvec3 ijk(0.0);
        ijk[axis] = slice;
        ijk[(axis + 1) % 3] = (c & 1) ? dims[(axis + 1) % 3] - 1 : 0;
        ijk[(axis + 2) % 3] = (c & 2) ? dims[(axis + 2) % 3] - 1 : 0;
        const glm::dvec3 u = plane.toCamera(origin + spacing * ijk);
        u2min = std::min(u2min, u.z);
        lateral2 = std::max(lateral2, u.x * u.x + u.y * u.y);
    }
    double jacobian2 = 0.0;
    if (plane.orthographic) {
        jacobian2 = std::max(plane.fPx * plane.fPx, 1.0);
    } else {
        if (!(u2min > plane.nearDepth)) return std::numeric_limits<double>::infinity();
        const double g = plane.fPx / u2min;
        jacobian2 = g * g * (2.0 + lateral2 / (u2min * u2min)) + 1.0;
    }
    const double sigma = settings.kernelScale * std::max({spacing.x, spacing.y, spacing.z});
    return settings.cutoffSigmas * std::sqrt(jacobian2 * sigma * sigma + 1.0);
}

// Pixels a point sprite covers beyond a quad for the footprint at camera point u: the square around
// the ellipse's longer side against its box. Elongated footprints (anisotropic spacing) waste that
// fill; quads cost five more vertices instead. headsq (3.2 x 3.2 x 1.5 mm), llvmpipe, 512x512, full
// EWA, two rounds each: points were faster at distance 8 and 5 (41-51 and 100-142 px over the slices'
// centres), even at 3.5 and 2.5 (192-316, 348-699), 1.15x slower at 1.8 (605-1,630), 2.3x at 1.2.
constexpr double kPointExcessPx2 = 400.0;
double pointExcessPx2(glm::dvec3 u, const glm::dmat3& varianceCamera, const ImagePlane& plane,
                      const SplatSettings& settings, FilterMode filter) {
    const Footprint f = projectKernel(u, varianceCamera, plane.fPx, filter == FilterMode::Adaptive ? FilterMode::Ewa : filter,
                                      glm::dmat2(1.0), plane.orthographic);
    const double hx = settings.cutoffSigmas * std::sqrt(f.variancePx[0][0]);
    const double hy = settings.cutoffSigmas * std::sqrt(f.variancePx[1][1]);
    const double side = 2.0 * std::max(hx, hy) + 1.0;
    return side * side - (2.0 * hx + 1.0) * (2.0 * hy + 1.0);
}

void setShadingUniforms(GLuint p, const ShadingParams& sp) {
    glUniform1f(glGetUniformLocation(p, "uShadingParams.ambient"), float(sp.ambient));
    glUniform1f(glGetUniformLocation(p, "uShadingParams.diffuse"), float(sp.diffuse));
    glUniform1f(glGetUniformLocation(p, "uShadingParams.specular"), float(sp.specular));
    glUniform1f(glGetUniformLocation(p, "uShadingParams.shininess"), float(sp.shininess));
    glUniform1f(glGetUniformLocation(p, "uShadingParams.flatGradient"), float(sp.flatGradient));
}

// Pixel rectangle a slice's splats can touch: the corners of the in-slice box [lo, hi] holding its
// drawn voxels, projected and grown by the largest footprint. The whole image when the box reaches
// the near plane.
struct Rect {
    int x0, y0, x1, y1;
};
Rect sliceRect(const glm::dvec3& origin, const glm::dvec3& spacing, const ImagePlane& plane, int axis, int slice,
               glm::u16vec2 lo, glm::u16vec2 hi, double margin) {
    const Rect all{0, 0, plane.width, plane.height};
    if (!std::isfinite(margin)) return all;
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int corner = 0; corner < 4; ++corner) {
        glm::dvec3 ijk(0.0);
        ijk[axis] = slice;
        ijk[a] = (corner & 1) ? hi.x : lo.x;
        ijk[b] = (corner & 2) ? hi.y : lo.y;
        const glm::dvec3 u = plane.toCamera(origin + spacing * ijk);
        if (!plane.orthographic && !(u.z > plane.nearDepth)) return all;
        const glm::dvec2 p = plane.project(u);
        x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
    }
    Rect r{int(std::floor(x0 - margin - 1)), int(std::floor(y0 - margin - 1)), int(std::ceil(x1 + margin + 1)),
           int(std::ceil(y1 + margin + 1))};
    r.x0 = std::clamp(r.x0, 0, plane.width), r.x1 = std::clamp(r.x1, 0, plane.width);
    r.y0 = std::clamp(r.y0, 0, plane.height), r.y1 = std::clamp(r.y1, 0, plane.height);
    return r;
}

// How many iterations the driver lets one invocation's loops run: a loop of 2^20 iterations counts
// them. llvmpipe stops it at 65535 (its LP_MAX_TGSI_LOOP_ITERATIONS, shared by every loop of the
// shader), and then silently ends every later loop after one iteration. 0: it ran to the end.
uint32_t measureLoopLimit() {
    constexpr GLuint kTrip = 1u << 20;
    const GLuint program = gl::buildComputeProgram("loop_limit", programSource("loop_limit", "", "loop_limit.comp").c_str());
    GLuint buffer = 0;
    glCreateBuffers(1, &buffer);
    glNamedBufferStorage(buffer, 4, nullptr, 0);
    glUseProgram(program);
    glUniform1ui(glGetUniformLocation(program, "uN"), kTrip);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint iterations = 0;
    glGetNamedBufferSubData(buffer, 0, 4, &iterations);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    glUseProgram(0);
    glDeleteBuffers(1, &buffer);
    glDeleteProgram(program);
    return iterations < kTrip ? iterations : 0;
}

} // namespace

SplatRenderer::SplatRenderer() : m_gl(std::make_unique<Gl>()) {
    if (epoxy_gl_version() < 45)
        throw GlError("SplatRenderer", "needs OpenGL 4.5 core, the current context has " + glVersionString());
    installGlDebugCallback();
    Gl& g = *m_gl;
    g.splatProgram(0);   // the common variant: a broken shader fails here, not in the first frame
    for (int heat = 0; heat < 2; ++heat) {
        const std::string defines = heat ? "#define HEATMAP\n" : "";
        g.compositePrograms[size_t(heat)] =
            gl::buildProgram("sheet_composite", programSource("sheet_composite", defines, "fullscreen.vert").c_str(),
                             programSource("sheet_composite", defines, "sheet_composite.frag").c_str());
    }
    // A full-screen pass: the one triangle of fullscreen.vert, then `fragment`.
    auto fullscreen = [](const char* program, const char* fragment) {
        return gl::buildProgram(program, programSource(program, "", "fullscreen.vert").c_str(),
                                programSource(program, "", fragment).c_str());
    };
    g.opaqueMaskProgram = fullscreen("opaque_mask", "opaque_mask.frag");
    g.resolveProgram = fullscreen("xray_resolve", "xray_resolve.frag");
    g.displayProgram = fullscreen("display", "display.frag");
    g.commandsProgram =
        gl::buildComputeProgram("bucket_commands", programSource("bucket_commands", "", "bucket_commands.comp").c_str());
    g.patchProgram = gl::buildComputeProgram("patch_modes", programSource("patch_modes", "", "patch_modes.comp").c_str());
    g.opaqueTilesProgram = gl::buildComputeProgram(
        "opaque_tiles", programSource("opaque_tiles", opaqueTileDefine(), "opaque_tiles.comp").c_str());
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
    if (glRendererName().rfind("llvmpipe", 0) == 0) {
        g.runLanes = 8;
        g.listChunkSlices = 16;
    }
    g.loopLimit = measureLoopLimit();
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
    // GPU memory: the classes (2 bytes a voxel), the LUT, the lists of the view's axis (the largest
    // counts): entries (2 bytes each), runs (16 bytes) and where each slice's runs start (4 bytes a
    // slice), and one command array (16 bytes a run of the axis with the most), against what the driver
    // reports free (plus what the current scene holds, which is replaced) and the optional limit.
    std::array<AxisBuffers, 3> axes;   // host side only until the check passes
    uint64_t listBytes = 0;
    size_t mostRuns = 1;
    for (int axis = 0; axis < 3; ++axis) {
        const AxisLists& lists = scene.lists[size_t(axis)];
        AxisBuffers& a = axes[size_t(axis)];
        const size_t n = lists.runs.size();
        a.hostEntries = lists.entries;
        a.hostEntries.resize(std::max<size_t>((lists.entries.size() + 1) / 2, 1) * 2, 0);
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
        listBytes = std::max(listBytes, a.gpuBytes());
        mostRuns = std::max(mostRuns, a.hostRuns.size());
    }
    const uint64_t commandBytes = mostRuns * 32;   // both layouts (bucket_commands.comp)
    uint64_t needed = scene.classes.size() * sizeof(uint16_t) + scene.lut.size() * sizeof(glm::vec4) + listBytes +
                      commandBytes + gradientBufferBytes(scene.gradients.size());
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

    if (!g.lutBuffer) {
        glCreateBuffers(1, &g.lutBuffer);
        glNamedBufferStorage(g.lutBuffer, GLsizeiptr(kLutSize * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_STORAGE_BIT);
        glCreateTextures(GL_TEXTURE_BUFFER, 1, &g.lutTexture);
        glTextureBuffer(g.lutTexture, GL_RGBA32F, g.lutBuffer);
        checkAllocation("LUT buffer", scene.name, needed, freeBytes);
    }
    g.sceneBytes = scene.classes.size() * sizeof(uint16_t) + kLutSize * sizeof(glm::vec4);

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
    setLut(scene.lut);
    m_stats.uploadBytes += sceneUpload + gradientUpload;
    checkGlErrors("SplatRenderer::setScene");
}

void SplatRenderer::setGradients(const SplatScene& scene) {
    Gl& g = *m_gl;
    if (!g.classTexture || scene.dims != g.dims)
        throw RenderError("SplatRenderer::setGradients: call setScene with scene '" + scene.name + "' first");
    // Packed gradients, 3 bytes a voxel, when the scene has them (one word otherwise: a valid binding).
    const size_t bytes = gradientBufferBytes(scene.gradients.size());
    std::vector<uint8_t> packed(bytes, 0);
    for (size_t v = 0; v < scene.gradients.size(); ++v)
        for (size_t k = 0; k < 3; ++k) packed[3 * v + k] = uint8_t(scene.gradients[v] >> (8 * k));
    glDeleteBuffers(1, &g.gradientBuffer);
    glCreateBuffers(1, &g.gradientBuffer);
    glNamedBufferStorage(g.gradientBuffer, GLsizeiptr(bytes), packed.data(), 0);
    checkAllocation("gradients", scene.name, bytes, freeGpuMemoryBytes());
    g.sceneBytes += bytes - g.gradientBytes;
    g.gradientBytes = bytes;
    g.hasGradients = scene.gradients.size() == scene.classes.size();
    m_stats.uploadBytes = bytes;
    g.uploadedSinceFrame += bytes;
}

void SplatRenderer::setLut(const Lut& lut) {
    Gl& g = *m_gl;
    if (lut.size() != size_t(kLutSize)) throw RenderError("LUT must have " + std::to_string(kLutSize) + " entries");
    if (!g.lutBuffer) throw RenderError("SplatRenderer::setLut called before setScene");
    glNamedBufferSubData(g.lutBuffer, 0, GLsizeiptr(lut.size() * sizeof(glm::vec4)), lut.data());
    g.lut = lut;
    ++g.lutVersion;
    m_stats.uploadBytes = lut.size() * sizeof(glm::vec4);
    g.uploadedSinceFrame += m_stats.uploadBytes;
    checkGlErrors("SplatRenderer::setLut");
}

void SplatRenderer::render(const ImagePlane& plane, const SplatSettings& settings) {
    std::string refused = drawFrame(plane, settings, false);
    // Auto: one slice's tile lists did not fit; the same frame through the rasteriser, with tiles'
    // semantics.
    if (!refused.empty() && settings.primitive == SplatSettings::Primitive::Auto)
        refused = drawFrame(plane, settings, true);
    if (!refused.empty()) throw RenderError(refused);
}

std::string SplatRenderer::drawFrame(const ImagePlane& plane, const SplatSettings& settings, bool rasterise) {
    Gl& g = *m_gl;
    const auto cpuStart = std::chrono::steady_clock::now();
    if (plane.width < 1 || plane.height < 1 || plane.width > 16384 || plane.height > 16384)
        throw RenderError("image size " + std::to_string(plane.width) + "x" + std::to_string(plane.height) +
                          " out of range (1..16384)");
    if (!g.classTexture) throw RenderError("SplatRenderer::render called before setScene");
    requireGradients(settings, g.hasGradients, g.sceneName);
    g.ensureTargets(plane.width, plane.height);

    using Primitive = SplatSettings::Primitive;
    if (settings.primitive == Primitive::Tiles && settings.compositing == Compositing::SplatEverySample)
        throw RenderError("tiled splatting composites sheets and X-ray only: splat-every-sample needs points or "
                          "quads (its order within a slice matters)");
    // Auto tiles sheets and X-ray. A chunk of slices whose lists do not fit the texel buffer they are
    // read through goes in parts, down to single slices; where one slice's do not fit, auto draws the
    // frame again rasterised (render()). (Deciding before the frame from a bound on footprint
    // size rasterised bonsai at distance 1.6 and nearer, 4-8x slower than tiles.)
    const Traversal trav = chooseTraversal(plane);
    const uint64_t listUpload = g.makeResident(trav.axis);
    const AxisBuffers& axis = g.axes[size_t(trav.axis)];
    std::array<bool, kBuckets> active = activeBuckets(g.lut);
    if (settings.drawAllBuckets) active.fill(true);
    // Splats each slice submits (its active runs' voxels), and the frame's.
    std::vector<uint64_t> sliceSubmitted(axis.sliceRuns.size() - 1, 0);
    for (size_t slice = 0; slice + 1 < axis.sliceRuns.size(); ++slice)
        for (uint32_t r = axis.sliceRuns[slice]; r < axis.sliceRuns[slice + 1]; ++r)
            sliceSubmitted[slice] += active[axis.buckets[r]] ? axis.voxels[r] : 0;
    const uint64_t submitted = std::accumulate(sliceSubmitted.begin(), sliceSubmitted.end(), uint64_t(0));
    const bool ftb = frontToBack(settings);
    const bool earlyTermination = ftb && settings.opaqueAlpha < 1.0;
    using Shading = SplatSettings::Shading;
    // Adaptive, where the volume's depth range puts every patch in one filter: that filter's code draws
    // the frame, and the patches are set to it without their pass (hysteresis reads them next frame).
    const FilterMode drawnFilter =
        settings.filter == FilterMode::Adaptive
            ? uniformAdaptiveFilter(g.dims, g.origin, g.spacing, plane, settings).value_or(FilterMode::Adaptive)
            : settings.filter;
    const int variant = (settings.counters ? kCounters : 0) | (settings.surfaceFlatten > 1.0 ? kSurface : 0) |
                        (settings.shading == Shading::PerSplat ? kSplatShading : 0) |
                        (settings.shading == Shading::PerFragment ? kFragmentShading : 0) |
                        (settings.heatmap ? kHeatmap : 0) | (drawnFilter == FilterMode::Adaptive ? kAdaptive : 0) |
                        (earlyTermination && settings.occlusionCulling ? kOcclusion : 0);
    const bool tiles = settings.primitive == Primitive::Tiles || (tiledSplatting(settings) && !rasterise);
    // Rasterised, slice by slice: points cost one vertex and one primitive a splat instead of six and
    // two; they need the slice's footprints to fit the largest point size, and a guard band, since a
    // point is clipped by its centre. Auto and raster take quads for the other slices, and where the
    // slice's centre voxel says points would waste fill (pointExcessPx2()).
    const uint32_t slices = uint32_t(g.dims[trav.axis]);
    const double pointFits = 0.5 * (g.maxPointSize - 1.0);   // gl_PointSize = 2 h + 1
    const glm::dmat3 varianceCamera = kernelVarianceCamera(settings.kernelScale * g.spacing, plane.viewFromObject);
    enum SliceDraw : uint8_t { kNothing, kPoints, kQuads };   // kNothing: no active bucket
    std::vector<SliceDraw> sliceDraw(slices, kNothing);
    // Each drawn slice's bound on its footprints' half extent: also how far rasterised sheets reach.
    std::vector<double> sliceBound(slices, std::numeric_limits<double>::infinity());
    if (!tiles) {
        double worst = 0.0;
        for (uint32_t slice = 0; slice < slices; ++slice) {
            bool drawn = false;
            for (uint32_t r = axis.sliceRuns[slice]; r < axis.sliceRuns[slice + 1] && !drawn; ++r) drawn = active[axis.buckets[r]];
            if (!drawn) continue;
            const double b = sliceBound[slice] =
                sliceHalfExtentBound(g.dims, g.origin, g.spacing, plane, settings, trav.axis, int(slice));
            worst = std::max(worst, b);
            bool points = settings.primitive != Primitive::Quads && b <= pointFits;
            if (points && settings.primitive != Primitive::Points) {
                glm::dvec3 centre(0.0);
                centre[trav.axis] = slice;
                centre[(trav.axis + 1) % 3] = 0.5 * (g.dims[(trav.axis + 1) % 3] - 1);
                centre[(trav.axis + 2) % 3] = 0.5 * (g.dims[(trav.axis + 2) % 3] - 1);
                points = pointExcessPx2(plane.toCamera(g.origin + g.spacing * centre), varianceCamera, plane, settings,
                                        settings.filter) <= kPointExcessPx2;
            }
            sliceDraw[slice] = points ? kPoints : kQuads;
        }
        if (settings.primitive == Primitive::Points && std::count(sliceDraw.begin(), sliceDraw.end(), kQuads) > 0)
            throw RenderError("point sprites cannot hold this view's footprints (up to " + std::to_string(worst) +
                              " px half extent, the driver's points reach " + std::to_string(pointFits) + ")");
    }

    // Nothing below throws before the queries end: a query left active would break the next frame
    // (NVIDIA keeps a deleted active query running).
    collectTimers();
    m_stats.frame = ++g.renders;
    g.firstUses = 0;
    const size_t slot = size_t(g.timerNext);
    const bool timed = m_stats.timed = !g.timerPending[slot];   // ring full of unfinished frames: skip, never stall
    if (timed) {
        g.timing = &g.laps[slot];
        g.timing->used = 0;
        g.lapPass.reset();
        g.lap(std::nullopt);   // the frame's start
    }
    if (settings.counters) glBeginQuery(GL_SAMPLES_PASSED, g.fragmentQuery);
    const int pointSlices = int(std::count(sliceDraw.begin(), sliceDraw.end(), kPoints));
    const float guard = pointSlices > 0 ? float(std::ceil(0.5 * g.maxPointSize) + 1.0) : 0.0f;
    const Compositing mode = settings.compositing;
    const bool sheets = mode == Compositing::SheetBackToFront || mode == Compositing::SheetFrontToBack;
    const bool reversed = ftb && !sheets;   // splat-every-sample, front to back: the exact reverse
    // Slices walk back to front, except front to back; sheets only turn the slice order, splat-every-
    // sample reverses everything (the vertex stage each run). Tiles read the commands by run.
    const bool descending = trav.descending != (ftb && sheets);
    if (tiles) g.updateCommands(trav.axis, false, false, settings.drawAllBuckets);
    else g.updateCommands(trav.axis, descending, reversed, settings.drawAllBuckets);
    const int refresh = opaqueRefreshSlices(settings);
    const bool xray = mode == Compositing::XRay;

    const float zero[4] = {0, 0, 0, 0};
    const float one = 1.0f;
    std::string refused;   // why this frame could not be drawn, when only drawing it tells
    glDisable(GL_SCISSOR_TEST);
    glClearNamedFramebufferfv(g.frameFbo, GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(g.frameFbo, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(g.frameFbo, GL_DEPTH, 0, &one);
    if (settings.counters) glClearNamedBufferData(g.counterBuffer, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    const GLenum bothTargets[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    const GLsizei targets = settings.heatmap ? 2 : 1;
    glNamedFramebufferDrawBuffers(g.frameFbo, targets, bothTargets);
    glNamedFramebufferDrawBuffers(g.sheetFbo, targets, bothTargets);

    if (settings.filter == FilterMode::Adaptive) {
        g.classifyPatches(plane, settings, trav.axis, drawnFilter);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    const GLuint p = tiles ? g.tileProgram(Gl::kTileSplat, variant & ~kHeatmap) : g.splatProgram(variant);
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
    glUniform1f(glGetUniformLocation(p, "uExtinctionScale"),
                float(settings.density / meanSpacing * g.spacing.x * g.spacing.y * g.spacing.z));
    glUniform1f(glGetUniformLocation(p, "uMaxHalfExtent"), float(settings.maxFootprintFraction * diagonal));
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
    // Where slice `slice`'s commands lie in the bound array (as bucket_commands.comp lays them out), and how
    // many there are.
    const uint32_t runCount = axis.runCount;
    auto sliceCommands = [&](uint32_t slice) {
        const uint32_t r0 = axis.sliceRuns[slice], n = axis.sliceRuns[slice + 1] - r0;
        const uint32_t first = descending ? runCount - axis.sliceRuns[slice + 1] : r0;
        return std::pair{reversed ? runCount - first - n : first, n};
    };
    // Draws the slices at draw positions k0 .. k1 - 1 (sliceAt(k): the slice drawn k-th), in that
    // order: one multi-draw per stretch of adjacent commands whose slices take the same primitive (a
    // slice without an active bucket draws nothing either way and joins any stretch).
    const GLint vertsPerSplat = glGetUniformLocation(p, "uVertsPerSplat");
    auto drawSlices = [&](uint32_t k0, uint32_t k1, auto sliceAt) {
        uint32_t first = 0, last = 0;
        bool asPoints = false;
        auto flush = [&] {
            if (last <= first) return;
            glUniform1i(vertsPerSplat, asPoints ? 1 : 6);
            glMultiDrawArraysIndirect(asPoints ? GL_POINTS : GL_TRIANGLES,
                                      reinterpret_cast<const void*>(size_t(asPoints ? first : runCount + first) * 16),
                                      GLsizei(last - first), 0);
        };
        for (uint32_t k = k0; k < k1; ++k) {
            const uint32_t slice = sliceAt(k);
            const auto [f, n] = sliceCommands(slice);
            if (n == 0) continue;
            if (sliceDraw[slice] == kNothing) {
                if (last > first && f == last) last = f + n;
                continue;
            }
            if (last <= first || f != last || (sliceDraw[slice] == kPoints) != asPoints) {
                flush();
                first = f;
                asPoints = sliceDraw[slice] == kPoints;
            }
            last = f + n;
        }
        flush();
    };
    // Front to back, every `refresh` slices: pixels whose alpha reached opaqueAlpha get depth 0.5,
    // where splats (also at 0.5) fail GL_LESS; the tile map the vertex stage culls with is redone
    // once every occlusionSlices(settings) slices (`remap`).
    auto refreshOpaque = [&](GLuint fbo, bool remap) {
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
    };
    if (pointSlices > 0) glEnable(GL_PROGRAM_POINT_SIZE);
    const int guardInt = int(guard);
    glViewport(-guardInt, -guardInt, plane.width + 2 * guardInt, plane.height + 2 * guardInt);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);

    m_stats.slicesDrawn = 0;
    m_stats.tileEntries = 0;
    m_stats.tileListSplits = 0;

    if (tiles) {
        // Compute passes only: no framebuffer with attachments stays bound (the caller's window,
        // say). llvmpipe bins timestamp queries into a bound framebuffer's draws and runs dispatches
        // at once, so every pass's time landed in the lap before it.
        glBindFramebuffer(GL_FRAMEBUFFER, g.computeFbo);
        // Tiled splatting (tile_record.comp and after): splat records and per-tile counts, offsets, lists, then
        // one workgroup per tile composites. Ranks follow the compositing order. With early termination
        // the ranks go in chunks, each binned against the opaque-tile map the chunks before it left.
        const glm::ivec2 grid((plane.width + kSplatTilePx - 1) / kSplatTilePx,
                              (plane.height + kSplatTilePx - 1) / kSplatTilePx);
        const GLint tileCount = grid.x * grid.y;
        const size_t recordBytes = size_t(recordVec4s(variant)) * 16, texels = size_t(entryTexels(variant));
        // Chunks: occlusion ones (nextOcclusionChunk(), at most maxOcclusionChunk()), else listChunkSlices.
        const bool occlusion = variant & kOcclusion;
        uint32_t chunk = occlusion ? uint32_t(occlusionSlices(settings))
                                   : (g.listChunkSlicesSet ? g.listChunkSlicesSet : g.listChunkSlices);
        const uint32_t maxChunk = std::min(occlusion ? uint32_t(maxOcclusionChunk(settings)) : chunk, slices);
        const size_t binBytes = size_t(tileCount) * maxChunk * 4;
        // Records are numbered afresh in each part of a chunk, so they need room for the most splats any
        // maxChunk adjacent slices submit, not the frame's (a 512 x 512 x 400 scan: 120 MB, not 1.9 GB).
        uint64_t chunkSplats = 0, window = 0;
        for (uint32_t slice = 0; slice < slices; ++slice) {
            window += sliceSubmitted[slice] - (slice >= maxChunk ? sliceSubmitted[slice - maxChunk] : 0);
            chunkSplats = std::max(chunkSplats, window);
        }
        bool anyOpaque = false;   // occlusion: whether the map has an opaque tile yet
        GLuint segments = 1;      // workgroups a run is dealt to in the record pass (more where a loop limit cut one)
        const uint32_t partSlices = earlyTermination ? uint32_t(refresh) : 1;
        auto advance = [&](uint32_t& k0) {
            k0 += chunk;
            if (occlusion) chunk = uint32_t(nextOcclusionChunk(settings, int(k0), int(chunk), anyOpaque));
        };
        Gl::ensureBuffer(g.tileSplats, g.tileSplatBytes, std::max<uint64_t>(chunkSplats, 1) * recordBytes);
        Gl::ensureBuffer(g.tileBins, g.tileBinBytes, binBytes);
        Gl::ensureBuffer(g.tileState, g.tileStateBytes, (4 + size_t(tileCount)) * 4);
        Gl::ensureBuffer(g.tileBusy, g.tileBusyBytes, (4 + size_t(tileCount)) * 4);
        // The scatter's records (as many as the driver allows) and tile bases.
        Gl::bindTexels(g.tileSplatTexture, GL_RGBA32F, g.tileSplats,
                       GLsizeiptr(std::min<uint64_t>(g.tileSplatBytes / 16, g.texelCap()) * 16), 6);
        Gl::bindTexels(g.tileStateTexture, GL_R32UI, g.tileState, GLsizeiptr(g.tileStateBytes), 5);
        const GLuint offsets = g.tileProgram(Gl::kTileOffsets, 0);
        const GLuint bases = g.tileProgram(Gl::kTileBases, 0);
        const GLuint scatter = g.tileProgram(Gl::kTileScatter, variant & (kSplatShading | kFragmentShading | kOcclusion));
        const GLuint composite = g.tileProgram(
            Gl::kTileComposite,
            (variant & (kHeatmap | kSplatShading | kFragmentShading | kOcclusion)) | (xray ? Gl::kTileXRay : 0) |
                (columnRecurrence(drawnFilter, g.dims, g.origin, g.spacing, plane, settings) ? Gl::kTileColumnRecurrence : 0));
        glUniform2i(glGetUniformLocation(p, "uTiles"), grid.x, grid.y);
        glUniform1i(glGetUniformLocation(p, "uSlices"), GLint(slices));
        glUniform1i(glGetUniformLocation(p, "uRankDescending"), descending);
        g.useProgram(offsets);
        glUniform1i(glGetUniformLocation(offsets, "uTileCount"), tileCount);
        g.useProgram(bases);
        glUniform1i(glGetUniformLocation(bases, "uTileCount"), tileCount);
        g.useProgram(scatter);
        glUniform2i(glGetUniformLocation(scatter, "uTiles"), grid.x, grid.y);
        glUniform2f(glGetUniformLocation(scatter, "uViewport"), float(plane.width), float(plane.height));
        g.useProgram(composite);
        glUniform2i(glGetUniformLocation(composite, "uTiles"), grid.x, grid.y);
        glUniform1i(glGetUniformLocation(composite, "uRefresh"), earlyTermination ? refresh : 1);
        glUniform2f(glGetUniformLocation(composite, "uViewport"), float(plane.width), float(plane.height));
        glUniform2f(glGetUniformLocation(composite, "uCentrePx"), float(plane.centrePx.x), float(plane.centrePx.y));
        glUniform1f(glGetUniformLocation(composite, "uCutoff"), float(settings.cutoffSigmas));
        glUniform1f(glGetUniformLocation(composite, "uFPx"), float(plane.fPx));
        glUniform1f(glGetUniformLocation(composite, "uOpaqueAlpha"),
                    earlyTermination ? float(settings.opaqueAlpha) : 2.0f);
        glUniform1i(glGetUniformLocation(composite, "uFrontToBack"), ftb);
        glUniform1i(glGetUniformLocation(composite, "uOrtho"), plane.orthographic);
        setShadingUniforms(composite, sp);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, axis.runs);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, g.commands);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, g.tileSplats);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, g.tileBins);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, g.tileState);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, g.tileBusy);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, g.tileBusy);
        glBindImageTexture(0, g.image, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        glBindImageTexture(1, g.heat, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        for (uint32_t k0 = 0; k0 < slices && refused.empty(); advance(k0)) {
            const uint32_t chunkEnd = std::min(slices, k0 + chunk);
            // The chunk goes whole unless its lists do not fit; then in parts of ranks j0 .. j1 - 1, each
            // as many slices as fit the last time. The parts cull against the map the chunk started with,
            // and start where a refresh is due (a part holds a multiple of partSlices), so what is culled
            // and composited is what the CPU oracle's chunk gives.
            bool split = false;
            uint32_t j0 = k0, j1 = chunkEnd;
            while (j0 < chunkEnd && refused.empty()) {
                const uint32_t ranks = j1 - j0;
                auto next = [&] { j1 = std::min(chunkEnd, j1 + ranks); j0 += ranks; };
                // The part's slices, and so its runs, are contiguous (runs are sorted by slice).
                const uint32_t s0 = descending ? slices - j1 : j0, s1 = descending ? slices - j0 : j1;
                const uint32_t runFirst = axis.sliceRuns[s0], runs = axis.sliceRuns[s1] - runFirst;
                bool any = false;
                for (uint32_t r = runFirst; r < runFirst + runs && !any; ++r) any = active[axis.buckets[r]];
                if (!any) {
                    next();
                    continue;
                }
                const GLuint cullMap = split && occlusion ? g.chunkStartMap : g.opaqueTiles;
                if (settings.counters) {   // a part that does not fit goes again: it must not count twice
                    Gl::ensureBuffer(g.savedCounters, g.savedCounterBytes, kCounterSlots * 4);
                    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
                    glCopyNamedBufferSubData(g.counterBuffer, g.savedCounters, 0, 0, kCounterSlots * 4);
                }
                g.lap(GpuPass::Splats);
                glClearNamedBufferSubData(g.tileBins, GL_R32UI, 0, GLsizeiptr(size_t(tileCount) * ranks * 4),
                                          GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
                glClearNamedBufferSubData(g.tileState, GL_R32UI, 0, 16, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
                const GLuint groupsX = std::min<GLuint>(runs, 32768);
                g.useProgram(p);
                g.bindCullMap(cullMap);
                glUniform1ui(glGetUniformLocation(p, "uRunFirst"), runFirst);
                glUniform1ui(glGetUniformLocation(p, "uRuns"), runs);
                glUniform1ui(glGetUniformLocation(p, "uGroupsX"), groupsX);
                glUniform1i(glGetUniformLocation(p, "uRank0"), GLint(j0));
                glUniform1i(glGetUniformLocation(p, "uRanks"), GLint(ranks));
                glUniform1ui(glGetUniformLocation(p, "uSegments"), segments);
                glUniform1ui(glGetUniformLocation(p, "uProbe"), 2);
                glDispatchCompute(groupsX, (runs + groupsX - 1) / groupsX, segments);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);   // records: the scatter's texels

                g.lap(GpuPass::Offsets);
                g.useProgram(offsets);
                glUniform1i(glGetUniformLocation(offsets, "uRanks"), GLint(ranks));
                glDispatchCompute(GLuint((tileCount + 63) / 64), 1, 1);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
                g.useProgram(bases);
                glDispatchCompute(1, 1, 1);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                                GL_TEXTURE_FETCH_BARRIER_BIT);
                // Splats, entries (they size the lists' buffer), the busiest tile's entries and whether a
                // record invocation was cut short: the one wait of a part (a few bytes).
                GLuint counts[4] = {0, 0, 0, 0};
                glGetNamedBufferSubData(g.tileState, 0, sizeof(counts), counts);
                if (counts[3]) {   // llvmpipe's loop limit stopped a run part way: deal the runs wider
                    if (settings.counters)
                        glCopyNamedBufferSubData(g.savedCounters, g.counterBuffer, 0, 0, kCounterSlots * 4);
                    if (segments >= kMaxRunSegments) {
                        refused = "tiled splatting: the driver ends a shader's loops after " +
                                  std::to_string(g.loopLimit) + " iterations, too few for these footprints' boxes; "
                                  "use points or quads";
                        break;
                    }
                    segments *= 8;
                    continue;
                }
                // Texels of the lists, or of the records where they take more.
                const uint64_t needed = std::max(uint64_t(counts[1]) * texels, uint64_t(counts[0]) * recordVec4s(variant));
                const uint64_t limit = std::min(g.texelCap(), kTileListBudgetTexels);
                // The composite's loops: the busiest tile's entries and each rank (twice).
                const uint64_t loops = uint64_t(counts[2]) + 2 * uint64_t(ranks) + kCompositeLoopSlack;
                const bool overTexels = needed > (ranks > partSlices ? limit : g.texelCap());
                const bool overLoops = g.loopLimit && loops > g.loopLimit;
                if (overTexels || overLoops) {
                    const std::string slicesPut =
                        ranks == 1 ? std::string("one slice's ") : std::to_string(ranks) + " slices' ";
                    if (ranks <= partSlices && overTexels) {
                        refused = "tiled splatting: " + slicesPut + std::to_string(counts[0]) + " splats take " +
                                  std::to_string(counts[1]) + " tile entries, over GL_MAX_TEXTURE_BUFFER_SIZE (" +
                                  std::to_string(g.texelCap()) + " texels); use points or quads";
                        break;
                    }
                    if (ranks <= partSlices) {
                        refused = "tiled splatting: " + slicesPut + "splats put " + std::to_string(counts[2]) +
                                  " entries on one tile, more than the driver's limit of " +
                                  std::to_string(g.loopLimit) + " loop iterations a shader lets it walk; use points or quads";
                        break;
                    }
                    if (occlusion && !split) {   // nothing of this chunk is composited yet
                        const size_t mapBytes = g.opaqueMapBytes();
                        Gl::ensureBuffer(g.chunkStartMap, g.chunkStartMapBytes, mapBytes);
                        glCopyNamedBufferSubData(g.opaqueTiles, g.chunkStartMap, 0, 0, GLsizeiptr(mapBytes));
                    }
                    if (settings.counters)
                        glCopyNamedBufferSubData(g.savedCounters, g.counterBuffer, 0, 0, kCounterSlots * 4);
                    split = true;
                    ++m_stats.tileListSplits;
                    // Again with as many slices as the lists' (or the busiest tile's) share suggests, at most half.
                    const double over = std::max(double(needed) / double(limit),
                                                 g.loopLimit ? double(loops) / double(g.loopLimit) : 0.0);
                    const uint64_t share = std::min<uint64_t>(uint64_t(double(ranks) / over), ranks / 2);
                    j1 = j0 + partSlices * uint32_t(std::max<uint64_t>(1, share / partSlices));
                    continue;
                }
                m_stats.tileEntries += counts[1];
                Gl::ensureBuffer(g.tileList, g.tileListBytes, std::max<size_t>(counts[1], 1) * texels * 16);
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, g.tileList);

                g.lap(GpuPass::Scatter);
                g.useProgram(scatter);
                glUniform1i(glGetUniformLocation(scatter, "uRanks"), GLint(ranks));
                glDispatchCompute(std::clamp<GLuint>((counts[0] + 63) / 64, 1, 65535), 1, 1);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);

                g.lap(GpuPass::Composite);
                g.useProgram(composite);
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, g.opaqueTiles);
                glUniform1i(glGetUniformLocation(composite, "uRank0"), GLint(j0));
                glUniform1i(glGetUniformLocation(composite, "uRanks"), GLint(ranks));
                Gl::bindTexels(g.tileListTexture, GL_RGBA32F, g.tileList,
                               GLsizeiptr(std::max<GLuint>(counts[1], 1) * texels * 16), 0);
                glBindTextureUnit(1, g.lutTexture);
                // A workgroup per tile with entries (listed by the bases pass); with OCCLUSION it also
                // leaves the opaque-tile map for the next chunk.
                glDispatchComputeIndirect(0);
                glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
                next();
            }
            if (occlusion && !anyOpaque) anyOpaque = g.anyTileOpaque();
        }
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                        GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        if (xray) g.resolveXRay(plane.width, plane.height);
        for (uint32_t slice = 0; slice < slices; ++slice)
            for (uint32_t r = axis.sliceRuns[slice]; r < axis.sliceRuns[slice + 1]; ++r)
                if (active[axis.buckets[r]]) {
                    ++m_stats.slicesDrawn;
                    break;
                }
    } else if (reversed) {
        // Front to back "under" (src (1 - dst.a) + dst), in groups of `refresh` slices.
        glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_FALSE);
        auto sliceAt = [&](uint32_t k) { return descending ? k : slices - 1 - k; };   // BTF's reverse
        for (uint32_t k0 = 0; k0 < slices; k0 += uint32_t(refresh)) {
            const uint32_t k1 = std::min(slices, k0 + uint32_t(refresh));
            bool any = false;
            for (uint32_t k = k0; k < k1 && !any; ++k) any = sliceCommands(sliceAt(k)).second > 0;
            if (!any) continue;
            if (k0 > 0) refreshOpaque(g.depthFbo, true);
            g.lap(GpuPass::Splats);
            glBindFramebuffer(GL_FRAMEBUFFER, g.frameFbo);
            glViewport(-guardInt, -guardInt, plane.width + 2 * guardInt, plane.height + 2 * guardInt);
            drawSlices(k0, k1, sliceAt);
        }
        glDisable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
    } else if (!sheets) {
        glBindFramebuffer(GL_FRAMEBUFFER, g.frameFbo);
        glDisable(GL_DEPTH_TEST);
        if (xray) glBlendFunc(GL_ONE, GL_ONE);                 // order-free sums
        else glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);     // premultiplied "over", back to front
        g.lap(GpuPass::Splats);
        drawSlices(0, slices, [&](uint32_t k) { return descending ? slices - 1 - k : k; });
        if (xray) g.resolveXRay(plane.width, plane.height);
    } else {
        // Per slice: clear the sheet, add the slice's splats into it, composite it into the image.
        // Everything is scissored to the slice's reach; slices without an active bucket are skipped.
        const double hugeFootprint = settings.maxFootprintFraction * diagonal;
        const GLuint composite = g.compositePrograms[settings.heatmap ? 1 : 0];
        glBindTextureUnit(0, g.sheet);
        glBindTextureUnit(1, g.sheetHeat);
        glBindTextureUnit(2, g.image);
        bool stale = false;   // a refresh is due before the next drawn slice
        // Occlusion chunks as tiles lay them out (nextOcclusionChunk()): the opaque-tile map is made
        // where each starts, if anything was drawn since the last.
        const bool occlusion = variant & kOcclusion;
        uint32_t chunk = uint32_t(occlusionSlices(settings)), chunkEnd = chunk;
        bool anyOpaque = false, drawnSinceMap = false;
        for (uint32_t k = 0; k < slices; ++k) {
            const uint32_t slice = descending ? slices - 1 - k : k;
            stale = stale || (earlyTermination && k > 0 && k % uint32_t(refresh) == 0);
            for (; occlusion && k == chunkEnd; chunkEnd += chunk) {
                if (drawnSinceMap) {
                    refreshOpaque(g.sheetFbo, true);
                    stale = drawnSinceMap = false;
                    if (!anyOpaque && tiledSplatting(settings)) anyOpaque = g.anyTileOpaque();
                }
                chunk = uint32_t(nextOcclusionChunk(settings, int(chunkEnd), int(chunk), anyOpaque));
            }
            const uint32_t r0 = axis.sliceRuns[slice], r1 = axis.sliceRuns[slice + 1];
            // The sheet covers only the active runs' voxels: their in-slice box, projected.
            glm::u16vec2 lo(UINT16_MAX), hi(0);
            for (uint32_t r = r0; r < r1; ++r)
                if (active[axis.buckets[r]]) lo = glm::min(lo, axis.lo[r]), hi = glm::max(hi, axis.hi[r]);
            if (lo.x > hi.x) continue;   // no active bucket: nothing to draw or composite
            ++m_stats.slicesDrawn;
            const Rect rect = sliceRect(g.origin, g.spacing, plane, trav.axis, int(slice), lo, hi,
                                        std::min(sliceBound[slice], hugeFootprint));
            // A slice off the image draws nothing; with counters it is drawn under an empty scissor all
            // the same, so its splats pass the guards and are counted as the CPU oracle counts them.
            const bool offImage = rect.x0 >= rect.x1 || rect.y0 >= rect.y1;
            if (offImage && !settings.counters) continue;
            if (stale) refreshOpaque(g.sheetFbo, false);   // mark what earlier slices made opaque
            stale = false;
            // GL's rows run bottom up.
            g.lap(GpuPass::Splats);
            glEnable(GL_SCISSOR_TEST);
            if (offImage) glScissor(0, 0, 0, 0);
            else glScissor(rect.x0, plane.height - rect.y1, rect.x1 - rect.x0, rect.y1 - rect.y0);
            glClearNamedFramebufferfv(g.sheetFbo, GL_COLOR, 0, zero);
            if (settings.heatmap) glClearNamedFramebufferfv(g.sheetFbo, GL_COLOR, 1, zero);
            glBindFramebuffer(GL_FRAMEBUFFER, g.sheetFbo);

            glViewport(-guardInt, -guardInt, plane.width + 2 * guardInt, plane.height + 2 * guardInt);
            g.useProgram(p);
            glBindVertexArray(g.splatVao);
            glEnable(GL_BLEND);
            glBlendFunc(GL_ONE, GL_ONE);
            if (earlyTermination) {
                glEnable(GL_DEPTH_TEST);
                glDepthFunc(GL_LESS);   // splats lie at depth 0.5 like the mask: masked pixels reject them
                glDepthMask(GL_FALSE);
            } else {
                glDisable(GL_DEPTH_TEST);
            }
            drawSlices(0, 1, [&](uint32_t) { return slice; });

            g.lap(GpuPass::Composite);
            glBindFramebuffer(GL_FRAMEBUFFER, g.frameFbo);
            glViewport(0, 0, plane.width, plane.height);
            glDisable(GL_DEPTH_TEST);
            if (ftb) glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);   // "under": src (1 - dst.a) + dst
            else glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);                // "over"
            g.useProgram(composite);
            glBindVertexArray(g.emptyVao);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            drawnSinceMap = true;
        }
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_DEPTH_TEST);
        glDepthMask(GL_TRUE);
        glDepthFunc(GL_LESS);
    }
    if (pointSlices > 0) glDisable(GL_PROGRAM_POINT_SIZE);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    if (settings.counters) glEndQuery(GL_SAMPLES_PASSED);
    if (timed) {
        g.lap(std::nullopt);   // the frame's end
        g.timing = nullptr;
        g.timerPending[slot] = true;
        g.timerFrame[slot] = g.renders;
        g.timerFirstUses[slot] = g.firstUses;
        g.timerNext = (g.timerNext + 1) % kTimerRing;
    }
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlErrors("SplatRenderer::render");
    if (!refused.empty()) return refused;   // found mid-frame: reported once the queries ended

    m_stats.splatsDrawn = submitted;
    m_stats.pointSlices = pointSlices;
    m_stats.quadSlices = int(std::count(sliceDraw.begin(), sliceDraw.end(), kQuads));
    m_stats.tiles = tiles;
    m_stats.adaptiveAs = settings.filter == FilterMode::Adaptive ? drawnFilter : FilterMode::Adaptive;
    m_stats.uploadBytes = listUpload;   // uniforms, and the lists when the view's axis changed
    m_stats.frameUploadBytes = g.uploadedSinceFrame + listUpload;
    g.uploadedSinceFrame = 0;
    m_stats.hasCounters = settings.counters;
    if (settings.counters) {   // waits for the frame: for tests, benchmarks and the stats panel's opt-in
        GLuint64 fragments = 0;
        glGetQueryObjectui64v(g.fragmentQuery, GL_QUERY_RESULT, &fragments);
        m_stats.fragments = fragments;
        std::array<GLuint, kCounterSlots> c{};
        glGetNamedBufferSubData(g.counterBuffer, 0, sizeof(c), c.data());
        SplatCounters& out = m_stats.counters;
        out = {};
        out.visible = c[kVisible];
        out.culledTransparent = c[kTransparent];
        out.culledNear = c[kNear];
        out.culledDegenerate = c[kDegenerate];
        out.culledHuge = c[kHuge];
        out.culledOffscreen = c[kOffscreen];
        out.drawn = c[kDrawn];
        out.culledOccluded = c[kOccluded];
        for (int m = 0; m < 3; ++m) out.drawnPerMode[m] = c[size_t(kMode0 + m)];
    }
    m_stats.firstUsePrograms = g.firstUses;
    m_stats.cpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpuStart).count();
    return {};
}

std::string primitiveName(const FrameStats& f) {
    if (f.tiles) return "tiles";
    if (f.pointSlices == 0) return "quads";
    if (f.quadSlices == 0) return "point sprites";
    return "points and quads (quads in " + std::to_string(f.quadSlices) + " of " +
           std::to_string(f.pointSlices + f.quadSlices) + " slices)";
}

std::string tileSplitsText(const FrameStats& f) {
    if (f.tileListSplits == 0) return "";
    return "tile lists went again in fewer slices " + std::to_string(f.tileListSplits) +
           " times: too many entries at once for the list buffer, or on one tile for the driver's loop limit";
}

const char* gpuPassName(GpuPass pass) {
    switch (pass) {
    case GpuPass::Select: return "select buckets";
    case GpuPass::Patches: return "classify patches";
    case GpuPass::Splats: return "splats";
    case GpuPass::Offsets: return "tile offsets";
    case GpuPass::Scatter: return "tile scatter";
    case GpuPass::Composite: return "composite";
    case GpuPass::Opaque: return "opaque map";
    case GpuPass::Resolve: return "resolve";
    }
    return "?";
}

std::vector<uint8_t> SplatRenderer::patchModes(const ImagePlane& plane, const SplatSettings& settings) {
    Gl& g = *m_gl;
    if (!g.classTexture) throw RenderError("SplatRenderer::patchModes called before setScene");
    const size_t n = g.classifyPatches(plane, settings, chooseTraversal(plane).axis);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    std::vector<uint8_t> modes(n);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);   // rows of any number of patches, unpadded
    glGetTextureImage(g.patchTexture, 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, GLsizei(n), modes.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    checkGlErrors("SplatRenderer::patchModes");
    return modes;
}

void SplatRenderer::collectTimers() {
    Gl& g = *m_gl;
    for (int i = 0; i < kTimerRing; ++i) {
        if (!g.timerPending[size_t(i)]) continue;
        const Gl::Laps& laps = g.laps[size_t(i)];
        GLint ready = 0;   // the frame's end, its last query
        glGetQueryObjectiv(laps.queries[laps.used - 1], GL_QUERY_RESULT_AVAILABLE, &ready);
        if (!ready) continue;
        g.timerPending[size_t(i)] = false;
        if (g.timerFrame[size_t(i)] <= g.newestTimed) continue;   // keep the newest finished frame's times
        g.newestTimed = g.timerFrame[size_t(i)];
        std::vector<GLuint64> t(laps.used);
        for (size_t j = 0; j < laps.used; ++j) glGetQueryObjectui64v(laps.queries[j], GL_QUERY_RESULT, &t[j]);
        m_stats.gpuFrame = g.timerFrame[size_t(i)];
        m_stats.gpuFirstUsePrograms = g.timerFirstUses[size_t(i)];
        m_stats.gpuMs = double(t.back() - t.front()) * 1e-6;
        m_stats.passMs = {};
        for (size_t j = 0; j + 1 < laps.used; ++j)
            if (laps.passes[j]) m_stats.passMs[size_t(*laps.passes[j])] += double(t[j + 1] - t[j]) * 1e-6;
    }
}

namespace {

Image readTexture(GLuint texture, int w, int h) {
    Image img(w, h);
    if (!texture) return img;
    std::vector<float> raw(img.rgba.size());
    glGetTextureImage(texture, 0, GL_RGBA, GL_FLOAT, GLsizei(raw.size() * sizeof(float)), raw.data());
    const size_t row = size_t(w) * 4;
    for (int y = 0; y < h; ++y)   // GL's row 0 is the bottom
        std::copy_n(&raw[size_t(h - 1 - y) * row], row, &img.rgba[size_t(y) * row]);
    checkGlErrors("SplatRenderer::readback");
    return img;
}

} // namespace

Image SplatRenderer::readback() const { return readTexture(m_gl->image, m_gl->width, m_gl->height); }

Image SplatRenderer::readbackHeatmap() const { return readTexture(m_gl->heat, m_gl->width, m_gl->height); }

unsigned SplatRenderer::displayTexture(const float background[3], bool heatmap) {
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

} // namespace renderer
