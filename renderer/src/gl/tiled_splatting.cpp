// The tiled path (sheets and X-ray): per chunk of slices, the four compute passes of renderer/shaders/
// tile_*.comp (record, offsets and bases, scatter, composite), splitting a chunk whose lists do not fit.
#include "splat_renderer_state.h"

#include <algorithm>

namespace renderer {

namespace {

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

// Whether the tile composite may take the Gaussian down a column by recurrence (COLUMN_RECURRENCE): every
// footprint holds the 1-px low-pass (its conic's entries are at most 1) and the cutoff is at most 3 sigmas.
// Both bound its products (tile_composite.comp).
bool columnRecurrence(FilterMode drawn, glm::ivec3 dims, glm::dvec3 origin, glm::dvec3 spacing, const ImagePlane& plane,
                      const SplatSettings& s) {
    return s.cutoffSigmas <= 3.0 && footprintsHoldThePixel(drawn, dims, origin, spacing, plane, s);
}

} // namespace

std::string SplatRenderer::Gl::drawTiled(const FramePlan& f, FrameStats& stats) {
    Gl& g = *this;
    const ImagePlane& plane = f.plane;
    const SplatSettings& settings = f.settings;
    const AxisBuffers& axis = f.lists;
    const std::array<bool, kBuckets>& active = f.active;
    const std::vector<uint64_t>& sliceSubmitted = f.sliceSubmitted;
    const uint32_t slices = f.slices;
    const bool earlyTermination = f.earlyTermination, xray = f.xray, descending = f.descending, ftb = f.ftb;
    const int variant = f.variant, refresh = f.refresh;
    const FilterMode drawnFilter = f.drawnFilter;
    const GLuint p = f.program;
    const ShadingParams& sp = settings.shadingParams;
    std::string refused;   // why this frame could not be drawn, when only drawing it tells
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
    // 1. Chunks of slices, and the buffers their records, counts and busy tiles need.
    // Chunks: occlusion ones (nextOcclusionChunk(), at most maxOcclusionChunk()), else listChunkSlices.
    const bool occlusion = variant & kOcclusion;
    uint32_t chunk = occlusion ? uint32_t(occlusionSlices(settings))
                               : (g.listChunkSlicesSet ? g.listChunkSlicesSet : g.driver.listChunkSlices);
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
    // A GPU reads nothing back inside the frame (DriverProfile::deferredListChecks): no part is checked
    // and none goes again; the lists take the capacity earlier frames measured, and the frame's figures
    // are read once it has finished (frame_status.cpp). A frame whose chunks may submit more records than
    // one buffer texture shows the scatter goes the checked way, in parts, from the start.
    const bool recordsFit = chunkSplats * uint64_t(recordVec4s(variant)) <= std::min(g.texelCap(), kTileListBudgetTexels);
    const bool deferred = g.driver.deferredListChecks && !g.checkedFrame && recordsFit;
    // Workgroups a run is dealt to in the record pass (more where a loop limit cut one).
    GLuint segments = deferred ? g.recordSegments : 1;
    const uint32_t partSlices = earlyTermination ? uint32_t(refresh) : 1;
    auto advance = [&](uint32_t& k0) {
        k0 += chunk;
        if (occlusion) chunk = uint32_t(nextOcclusionChunk(settings, int(k0), int(chunk), anyOpaque));
    };
    Gl::ensureBuffer(g.tileSplats, g.tileSplatBytes, std::max<uint64_t>(chunkSplats, 1) * recordBytes, "splat records");
    Gl::ensureBuffer(g.tileBins, g.tileBinBytes, binBytes, "tile counts");
    Gl::ensureBuffer(g.tileState, g.tileStateBytes, (4 + size_t(tileCount)) * 4, "tile offsets");
    Gl::ensureBuffer(g.tileBusy, g.tileBusyBytes, (4 + size_t(tileCount)) * 4, "busy-tile list");
    // The scatter's records (as many as the driver allows) and tile bases.
    Gl::bindTexels(g.tileSplatTexture, GL_RGBA32F, g.tileSplats,
                   GLsizeiptr(std::min<uint64_t>(g.tileSplatBytes / 16, g.texelCap()) * 16), 6);
    Gl::bindTexels(g.tileStateTexture, GL_R32UI, g.tileState, GLsizeiptr(g.tileStateBytes), 5);
    StatusSlot& status = g.beginStatus();
    // Deferred: the lists' room in entries, from the most a part took in earlier frames (first: four tiles
    // a splat), within what one buffer texture holds.
    uint64_t capacity = 0;
    if (deferred) {
        const uint64_t first = std::min<uint64_t>(4 * std::max<uint64_t>(chunkSplats, 1), kTileListBudgetTexels / texels);
        capacity = std::clamp<uint64_t>(g.listCapacity ? g.listCapacity : first, 1, g.texelCap() / texels);
        Gl::ensureBuffer(g.tileList, g.tileListBytes, capacity * texels * 16, "tile lists");
    }
    // 2. The passes' programs, their uniforms for this frame, and the bindings every part shares.
    const GLuint offsets = g.tileProgram(Gl::kTileOffsets, 0);
    const GLuint bases = g.tileProgram(Gl::kTileBases, 0);
    const GLuint scatter = g.tileProgram(Gl::kTileScatter, variant & (kSplatShading | kFragmentShading | kOcclusion));
    // The composite's layout by driver (a column per invocation on llvmpipe, a pixel on a GPU); only the
    // column layout takes the Gaussian by recurrence.
    const int compositeLayout =
        g.driver.compositePerPixel ? Gl::kTileCompositePixels
        : columnRecurrence(drawnFilter, g.dims, g.origin, g.spacing, plane, settings) ? Gl::kTileColumnRecurrence
                                                                                     : 0;
    const GLuint composite = g.tileProgram(
        Gl::kTileComposite, (variant & (kHeatmap | kSplatShading | kFragmentShading | kOcclusion)) |
                                (xray ? Gl::kTileXRay : 0) | compositeLayout);
    glUniform2i(glGetUniformLocation(p, "uTiles"), grid.x, grid.y);
    glUniform1i(glGetUniformLocation(p, "uSlices"), GLint(slices));
    glUniform1i(glGetUniformLocation(p, "uRankDescending"), descending);
    g.useProgram(offsets);
    glUniform1i(glGetUniformLocation(offsets, "uTileCount"), tileCount);
    g.useProgram(bases);
    glUniform1i(glGetUniformLocation(bases, "uTileCount"), tileCount);
    glUniform1i(glGetUniformLocation(bases, "uBatches"), g.driver.compositePerPixel);
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
    // 3. Chunk by chunk, in parts where its lists do not fit: record, offsets and bases, scatter, composite.
    for (uint32_t k0 = 0; k0 < slices && refused.empty() && !g.stopHere(); advance(k0)) {
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
            if (settings.counters && !deferred) {   // a part that does not fit goes again: it must not count twice
                Gl::ensureBuffer(g.savedCounters, g.savedCounterBytes, kCounterSlots * 4, "saved counters");
                glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
                glCopyNamedBufferSubData(g.counterBuffer, g.savedCounters, 0, 0, kCounterSlots * 4);
            }
            // 3a. Record: the part's splats and each tile's count per rank (tile_record.comp).
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

            // 3b. Counts to offsets, per tile and then over the tiles (tile_offsets.comp, tile_bases.comp).
            g.lap(GpuPass::Offsets);
            g.useProgram(offsets);
            glUniform1i(glGetUniformLocation(offsets, "uRanks"), GLint(ranks));
            glDispatchCompute(GLuint((tileCount + 63) / 64), 1, 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            g.useProgram(bases);
            // The composite's loops: the busiest tile's entries and each rank (twice); a pixel per
            // invocation also loops over the batches of 64 entries (at most one more a rank).
            const uint64_t loopExtra = (g.driver.compositePerPixel ? 3 : 2) * uint64_t(ranks) + kCompositeLoopSlack;
            glUniform1ui(glGetUniformLocation(bases, "uLoopExtra"), GLuint(loopExtra));
            glDispatchCompute(1, 1, 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
                            GL_TEXTURE_FETCH_BARRIER_BIT);
            // 3c. Read back what the part needs; a run cut short, lists too long or a tile too busy: again,
            //     dealt wider or in fewer slices (or refused where one slice is too much). Deferred: none
            //     of that; the lists hold `capacity` entries.
            // Splats, entries (they size the lists' buffer), the busiest tile's entries and whether a
            // record invocation was cut short: the one wait of a part (a few bytes).
            GLuint counts[4] = {0, 0, 0, 0};
            if (deferred) counts[1] = GLuint(capacity);
            else g.readBuffer(g.tileState, 0, sizeof(counts), counts);
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
            const uint64_t loops = uint64_t(counts[2]) + (g.driver.compositePerPixel ? counts[2] / 64 : 0) + loopExtra;
            const bool overTexels = !deferred && needed > (ranks > partSlices ? limit : g.texelCap());
            const bool overLoops = !deferred && g.loopLimit && loops > g.loopLimit;
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
                    Gl::ensureBuffer(g.chunkStartMap, g.chunkStartMapBytes, mapBytes, "opaque-tile map's copy");
                    glCopyNamedBufferSubData(g.opaqueTiles, g.chunkStartMap, 0, 0, GLsizeiptr(mapBytes));
                }
                if (settings.counters)
                    glCopyNamedBufferSubData(g.savedCounters, g.counterBuffer, 0, 0, kCounterSlots * 4);
                split = true;
                ++stats.tileListSplits;
                // Again with as many slices as the lists' (or the busiest tile's) share suggests, at most half.
                const double over = std::max(double(needed) / double(limit),
                                             g.loopLimit ? double(loops) / double(g.loopLimit) : 0.0);
                const uint64_t share = std::min<uint64_t>(uint64_t(double(ranks) / over), ranks / 2);
                j1 = j0 + partSlices * uint32_t(std::max<uint64_t>(1, share / partSlices));
                continue;
            }
            if (!deferred) {
                stats.tileEntries += counts[1];
                Gl::ensureBuffer(g.tileList, g.tileListBytes, std::max<size_t>(counts[1], 1) * texels * 16, "tile lists");
            }
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, g.tileList);

            // 3d. Scatter: each splat into its tiles' lists (tile_scatter.comp), a grid the bases pass sized.
            g.lap(GpuPass::Scatter);
            g.useProgram(scatter);
            glUniform1i(glGetUniformLocation(scatter, "uRanks"), GLint(ranks));
            glUniform1ui(glGetUniformLocation(scatter, "uListCapacity"), counts[1]);
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, g.scatterArgs);
            glDispatchComputeIndirect(0);
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, g.tileBusy);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);

            // 3e. Composite: a workgroup per busy tile (tile_composite.comp).
            g.lap(GpuPass::Composite);
            g.useProgram(composite);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, g.opaqueTiles);
            glUniform1i(glGetUniformLocation(composite, "uRank0"), GLint(j0));
            glUniform1i(glGetUniformLocation(composite, "uRanks"), GLint(ranks));
            Gl::bindTexels(g.tileListTexture, GL_RGBA32F, g.tileList,
                           GLsizeiptr(std::max<GLuint>(counts[1], 1) * texels * 16), 0);
            // The colour by the record's index: a LUT class, or with the 2D TF a cell of its table.
            glBindTextureUnit(1, g.tf2d && g.hasGradients ? g.tf2dTexture : g.lutTexture);
            // A workgroup per tile with entries (listed by the bases pass); with OCCLUSION it also
            // leaves the opaque-tile map for the next chunk.
            glDispatchComputeIndirect(0);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
            next();
        }
        // Deferred, the chunks double without asking whether a tile is opaque yet (culling itself runs on
        // the GPU either way); with counters they follow the CPU oracle's chunks, which ask.
        if (occlusion && !anyOpaque && (!deferred || settings.counters)) anyOpaque = g.anyTileOpaque();
    }
    g.endStatus(status, capacity, segments, deferred);
    // 4. X-ray's resolve; the slices drawn.
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    if (xray) g.resolveXRay(plane.width, plane.height);
    for (uint32_t slice = 0; slice < slices; ++slice)
        for (uint32_t r = axis.sliceRuns[slice]; r < axis.sliceRuns[slice + 1]; ++r)
            if (active[axis.buckets[r]]) {
                ++stats.slicesDrawn;
                break;
            }
    return refused;
}

} // namespace renderer
