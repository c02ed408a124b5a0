// The private state of SplatRenderer, shared by the files of renderer/src/gl/: every GL object it owns
// (struct SplatRenderer::Gl), the per-axis slice lists, and the plan of a frame its two paths read.
#pragma once
#include "renderer/gl/driver_profile.h"

#include "renderer/gl/splat_renderer.h"

#include "gl_util.h"
#include "renderer/errors.h"
#include "renderer/gl/gl_context.h"
#include "renderer/math/classifier.h"
#include "renderer/math/shading.h"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <map>
#include <optional>
#include <functional>
#include <set>
#include <string>
#include <vector>

namespace renderer {

// GPU timers in flight: a frame's laps are read back up to this many frames later.
constexpr int kTimerRing = 4;

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
    // The scene's entries, shared rather than copied (AxisLists::sharedEntries); may be null or empty.
    std::shared_ptr<const std::vector<uint16_t>> hostEntries;
    std::vector<glm::uvec4> hostRuns;  // the runs as the GPU reads them (at least one)

    // The entries' buffer: whole 32-bit words (the shaders read pairs), never empty (zero-sized stores
    // are errors).
    uint64_t entryBytes() const { return std::max<uint64_t>((hostEntries ? hostEntries->size() + 1 : 1) / 2, 1) * 4; }
    uint64_t gpuBytes() const {
        return entryBytes() + hostRuns.size() * sizeof(glm::uvec4) + sliceRuns.size() * 4;
    }
    void release() {
        const GLuint b[] = {entries, runs, sliceRunsBuffer};
        glDeleteBuffers(3, b);
        entries = runs = sliceRunsBuffer = 0;
    }
};

// Feature bits of a splat program variant: #defines of renderer/shaders/ (every set: programs.cmake).
enum SplatVariant { kCounters = 1, kSurface = 2, kSplatShading = 4, kFragmentShading = 8, kHeatmap = 16, kAdaptive = 32,
                    kOcclusion = 64, kGradientOpacity = 128,
                    kTf2d = 1 << 16 };   // past the bits of TilePass below: tile programs are keyed by both

// The LUT buffer: kLutSize class entries, then the kGradientBins gradient factors (GRADIENT_OPACITY in
// splat_footprint.glsl and near_kernels.comp read them at this offset), then the 2D TF's kTf2dCells
// (TF_2D, at kTf2dFirstEntry; the tiles' composite reads them through tf2dTexture, a view from there;
// allocated with the first 2D TF: Gl::lutBufferEntries).
constexpr size_t kTf2dFirstEntry = size_t(kLutSize) + size_t(kGradientBins);
constexpr size_t kLutBufferEntries = kTf2dFirstEntry + size_t(kTf2dCells);
static_assert(kLutSize == 4096 && kTf2dFirstEntry == 4352 && kTf2dGradientBins == 64,
              "splat_footprint.glsl and near_kernels.comp read the factors at texel 4096, the 2D TF at 4352, "
              "64 cells a value bin");
static_assert(kTf2dFirstEntry * 16 % 256 == 0, "a buffer texture's offset: a multiple of its alignment");

// Tiled splatting's vec4s per splat record and per list entry (tile_record.comp, tile_scatter.comp).
inline int recordVec4s(int bits) { return bits & kFragmentShading ? 4 : 3; }
inline int entryTexels(int bits) { return bits & (kSplatShading | kFragmentShading) ? 3 : 2; }

// The most workgroups the record pass deals one run to when llvmpipe's loop limit cuts a run short.
constexpr GLuint kMaxRunSegments = 4096;

// How a slice is drawn rasterised; kNothing: no active bucket.
enum SliceDraw : uint8_t { kNothing, kPoints, kQuads };

// What drawFrame decides before it issues anything (Gl::planFrame()), read by every step after it.
struct FramePlan {
    FramePlan(const ImagePlane& p, const SplatSettings& s, const AxisBuffers& l)
        : plane(p), settings(s), lists(l) {}
    const ImagePlane& plane;
    const SplatSettings& settings;
    const AxisBuffers& lists;          // the traversal axis's, resident
    Traversal trav{};
    uint64_t listUpload = 0;           // bytes makeResident() uploaded for this frame
    std::array<bool, kBuckets> active{};   // buckets drawn (all with drawAllBuckets)
    std::vector<uint64_t> sliceSubmitted;  // splats each slice submits (its active runs' voxels)
    uint64_t submitted = 0;            // the frame's
    bool ftb = false, earlyTermination = false;
    FilterMode drawnFilter = FilterMode::Ewa;   // Adaptive unless uniformAdaptiveFilter() decided the view
    int variant = 0;                   // SplatVariant bits
    bool tiles = false;                // compute passes, else the rasteriser
    uint32_t slices = 0;               // along the traversal axis
    glm::dmat3 varianceCamera{1.0};
    std::vector<SliceDraw> sliceDraw;  // rasterised: each slice's primitive
    std::vector<double> sliceBound;    // rasterised: each drawn slice's bound on its footprints' half extent
    int pointSlices = 0;
    float guard = 0;                   // pixels the viewport reaches past the image (points clip by centre)
    bool sheets = false, xray = false;
    bool reversed = false;             // splat-every-sample, front to back: the exact reverse
    bool descending = false;           // slices from the highest
    int refresh = 1;                   // opaqueRefreshSlices()
    GLuint program = 0;                // the splat (or tile record) program, set by prepareFrame()
};

struct SplatRenderer::Gl {
    std::map<int, GLuint> splatPrograms;   // by SplatVariant bits, built on first use
    std::array<GLuint, 2> compositePrograms{};   // without and with the heatmap
    GLuint opaqueMaskProgram = 0, resolveProgram = 0, displayProgram = 0;
    GLuint commandsProgram = 0, patchProgram = 0, opaqueTilesProgram = 0;
    GLuint nearKernelsProgram = 0, nearLayerProgram = 0;
    GLuint nearBuffer = 0;     // the near layer's kernels: a count, then two vec4s a kernel (near_kernels.comp)
    bool nearDrawn = false;    // the last frame drew a near layer (nearBuffer holds its kernels)
    GLuint splatVao = 0, emptyVao = 0;
    GLuint classTexture = 0;
    GLuint lutBuffer = 0, counterBuffer = 0, gradientBuffer = 0;
    GLuint patchTexture = 0;   // R8UI, a texel a patch (PatchGrid: columns x rows x slices)
    GLuint lutTexture = 0;   // buffer texture over lutBuffer (the tiles' composite)
    GLuint tf2dTexture = 0;  // buffer texture over lutBuffer's 2D TF cells (the tiles' composite, TF_2D)
    // lutBuffer's entries: kTf2dFirstEntry, or kLutBufferEntries from the first 2D TF on (a scene without
    // one keeps its GPU bytes). createLutBuffer makes it afresh, with its texture views.
    size_t lutBufferEntries = 0;
    void createLutBuffer(size_t entries);
    bool hasGradients = false;
    bool gradientOpacity = false;   // the last setLut had gradient factors (drawn with them when hasGradients)
    bool tf2d = false;              // the last setLut had a 2D TF table (drawn with it when hasGradients)
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
    // The GPU profile's tiled frames read nothing back while they run (DriverProfile::deferredListChecks,
    // frame_status.cpp): the lists hold listCapacity entries, from earlier frames' high-water mark, and
    // the record pass deals runs to recordSegments workgroups; each frame leaves its figures in one of two
    // status buffers, read once its fence says it has finished. The scatter dispatches itself
    // (scatterArgs, written by tile_bases.comp).
    struct StatusSlot {
        GLuint buffer = 0;
        GLsync fence = nullptr;
        bool pending = false;      // a deferred frame's figures not read yet
        uint64_t capacity = 0;     // the list entries that frame had room for
        GLuint segments = 1;       // the workgroups it dealt each run to
    };
    std::array<StatusSlot, 2> statusSlots;
    int statusNext = 0, statusLatest = -1;   // the slot the next frame takes; the last deferred frame's
    GLuint scatterArgs = 0;
    uint64_t listCapacity = 0;   // 0: no frame measured yet
    GLuint recordSegments = 1;
    bool checkedFrame = false;   // draw the next frame the checked way (a deferred frame redone)
    std::optional<std::pair<ImagePlane, SplatSettings>> lastRequest;   // render()'s, to draw it again
    int readBacks = 0;           // buffer reads issued by the frame being drawn (FrameStats::readBacks)
    // Every read of a buffer inside a frame goes through here, so the GPU profile's count can be tested.
    void readBuffer(GLuint buffer, GLintptr offset, GLsizeiptr bytes, void* data) {
        ++readBacks;
        glGetNamedBufferSubData(buffer, offset, bytes, data);
    }
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
    // Run lanes, chunk slices and the composite's layout by the kind of driver (set at construction).
    DriverProfile driver;
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
    // setInterrupt(): asked between chunks (tiled) and between slices (rasterised); once it says yes the
    // frame issues nothing more and render() throws Cancelled.
    std::function<bool()> interrupt;
    bool interrupted = false;
    bool stopHere() {
        if (!interrupted && interrupt && interrupt()) interrupted = true;
        return interrupted;
    }

    // == Methods, grouped by the file that defines them.
    // gpu_resources.cpp: render targets, growable buffers, buffer textures, teardown.
    ~Gl();
    void releaseTargets();
    // The frame passes' buffers, grown to the largest frame drawn, dropped for another volume (they regrow
    // on its first frame): a small scan opened after a large one does not keep the large one's.
    void releaseWorkingBuffers();
    void deleteWorkingBuffers();   // those buffers deleted and zeroed: what the release and ~Gl share
    static GLuint makeTexture(GLenum format, int w, int h);
    static GLuint makeFbo(std::initializer_list<GLuint> colours, GLuint depthTexture);
    // The frame's image, heatmap, sheets and depth at w x h (kept while the size stays) and the
    // opaque-tile map.
    void ensureTargets(int w, int h);
    // Grows `buffer` to at least `bytes` (with headroom); its contents are not kept. GL_OUT_OF_MEMORY
    // throws outOfMemory() naming the scene, `what` and the size, and leaves no buffer (the next frame
    // tries again).
    void ensureBuffer(GLuint& buffer, size_t& capacity, size_t bytes, const char* what);
    // Right after a GPU allocation of `bytes` for `what`: GL_OUT_OF_MEMORY becomes outOfMemory() naming
    // the scene and the frame's size; other GL errors stay GlErrors.
    void checkGpuAllocation(const char* what, uint64_t bytes) const;
    // " at 1920x1080": the size of the frame being drawn, for messages ("" outside a frame).
    std::string frameText() const;
    glm::ivec2 framePx{0};   // the frame being drawn (render() sets it; 0 outside a frame)
    // Binds to `unit` the buffer texture `texture` (created on first use) over the first `bytes` of
    // `buffer`: llvmpipe fetches texels lane by lane as a gather, storage-buffer values component by
    // component, so the passes read what they do not write as texels.
    static void bindTexels(GLuint& texture, GLenum format, GLuint buffer, GLsizeiptr bytes, GLuint unit);

    // program_variants.cpp: programs from renderer/shaders/.
    // The programs without variants, built once by SplatRenderer's constructor.
    void buildFixedPrograms();
    // The rasterised splat program of SplatVariant `bits`, built on first use.
    GLuint splatProgram(int bits);
    // Tiled splatting's passes (renderer/shaders/tile_*.comp); bits: SplatVariant features of the splat and
    // composite passes.
    enum TilePass { kTileSplat = 1 << 8, kTileOffsets = 2 << 8, kTileBases = 3 << 8, kTileScatter = 4 << 8,
                    kTileComposite = 5 << 8, kTileXRay = 1 << 12, kTileColumnRecurrence = 1 << 13,
                    kTileCompositePixels = 1 << 14 };
    GLuint tileProgram(int pass, int bits);

    // scene_upload.cpp: puts the lists of `axis` on the GPU in place of the resident axis's, so a scene
    // holds one axis, not three (sceneBytes counts the largest). Returns the bytes uploaded: 0 while the
    // view's major axis stays the same.
    uint64_t makeResident(int axis);

    // The steps of one frame, in the order SplatRenderer::drawFrame runs them.
    // 1. frame_plan.cpp: checks the request and decides the frame (the view's axis, made resident; the
    //    variant; tiles or the rasteriser; each slice's primitive). Throws before anything is issued.
    FramePlan planFrame(const ImagePlane& plane, const SplatSettings& settings, bool rasterise);
    // 2. frame_stats.cpp: starts the frame's timers (a ring slot, its first lap) and, with counters, its
    //    fragment query.
    void beginTiming(const SplatSettings& settings, FrameStats& stats);
    // 3. frame_passes.cpp: bucket selection, cleared targets, patch classification, and the splat program
    //    with its uniforms and bindings; sets f.program and leaves it bound.
    void prepareFrame(FramePlan& f);
    // 4. tiled_splatting.cpp: the compute passes; returns why the frame could not be drawn, or "".
    std::string drawTiled(const FramePlan& f, FrameStats& stats);
    //    raster_splatting.cpp: splat-every-sample, back to front or X-ray, or sheets, through the rasteriser.
    void drawRasterised(const FramePlan& f, FrameStats& stats);
    //    near_layer_pass.cpp: the kernels at the near plane, integrated along each pixel's ray, in front
    //    of the splats (renderer/oracle/near_layer.h); nothing where the near plane meets no kernel.
    void drawNearLayer(const FramePlan& f);
    // The last frame's near-layer counts (SplatCounters::nearLayer, droppedNear); waits for the frame.
    void readNearCounters(SplatCounters& out) const;
    //    frame_status.cpp: the status slot a deferred tiled frame writes (cleared, bound), and, after
    //    its passes, its fence. What finished frames left is read without waiting (pollStatus), or,
    //    for the frame being consumed, waiting (takeStatus): true when its image is wrong (lists too
    //    short, a run cut short, a tile over the loop limit), and capacity and segments grow for the
    //    next frames either way.
    StatusSlot& beginStatus();
    void endStatus(StatusSlot& slot, uint64_t capacity, GLuint segments, bool deferred);
    void pollStatus();
    bool takeStatus(StatusSlot& slot, FrameStats* stats);
    // 5. frame_stats.cpp: ends the frame's timers and fragment query.
    void endTiming(const FramePlan& f);
    // 6. frame_stats.cpp: waits for the frame and reads the counters into stats.counters and .fragments.
    void readCounters(FrameStats& stats);

    // frame_passes.cpp: passes both paths share.
    // Rewrites the indirect commands for the current LUT, axis and order (GPU only: nothing is
    // uploaded). Tiles read them ascending, by run.
    void updateCommands(int axis, bool descending, bool reversed, bool allBuckets);
    // The adaptive classifier once per patch (compute) into patchTexture; returns the patch count. Where
    // uniformAdaptiveFilter() decided the view (`decided`, else Adaptive), every patch is set to that
    // filter, what the pass would give, so hysteresis reads it next frame.
    size_t classifyPatches(const ImagePlane& plane, const SplatSettings& settings, int axis,
                           FilterMode decided = FilterMode::Adaptive);
    // Uniforms of splat_common.glsl for this view.
    void setCommonUniforms(GLuint p, const ImagePlane& plane, const SplatSettings& settings, int axis) const;
    // X-ray's sums become 1 - exp(-sum), in place (xray_resolve.frag).
    void resolveXRay(int w, int h);

    // occlusion.cpp: early termination and the opaque-tile map.
    // Front to back, before a group of slices: opaque pixels get depth 0.5 in `fbo` (and, with `remap`,
    // the opaque-tile map is redone).
    void maskOpaquePixels(const FramePlan& f, GLuint fbo, bool remap);
    // Whether any tile of the opaque-tile map is opaque (a wait for the passes before it).
    bool anyTileOpaque();
    // The opaque-tile map (binding 11) from the image's alpha: what occlusion culling reads.
    void updateOpaqueTiles(float opaqueAlpha);
    // The opaque-tile map occlusion culling reads (opaque_tiles_read.glsl).
    void bindCullMap(GLuint map);
    // The map: a word a tile, then one that says whether any tile is opaque.
    size_t opaqueMapBytes() const { return (size_t(tiles.x) * size_t(tiles.y) + 1) * 4; }

    // frame_stats.cpp: timestamps the start of `pass` in the frame being timed (nothing when the pass
    // goes on); no pass: the frame's start or end.
    void lap(std::optional<GpuPass> pass);
};

// The shading uniforms (struct ShadingParams in shading.glsl) of program `p`.
void setShadingUniforms(GLuint p, const ShadingParams& sp);
// Drains the GL errors after an allocation: true when one says out of memory (glGetError's
// GL_OUT_OF_MEMORY or the KHR_debug message of it); any other error throws GlError(stage, ...).
bool takeOutOfMemory(const std::string& stage);

// How many iterations the driver lets one invocation's loops run; 0: no limit found (program_variants.cpp).
uint32_t measureLoopLimit();

} // namespace renderer
