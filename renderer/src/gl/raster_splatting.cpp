// The rasterised path: each slice's splats as points or quads through splat.vert/splat.frag, blended
// straight into the image (splat-every-sample, back-to-front, X-ray) or into a sheet per slice.
#include "splat_renderer_state.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace renderer {

namespace {

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

} // namespace

void SplatRenderer::Gl::drawRasterised(const FramePlan& f, FrameStats& stats) {
    Gl& g = *this;
    const ImagePlane& plane = f.plane;
    const SplatSettings& settings = f.settings;
    const AxisBuffers& axis = f.lists;
    const std::array<bool, kBuckets>& active = f.active;
    const uint32_t slices = f.slices;
    const std::vector<SliceDraw>& sliceDraw = f.sliceDraw;
    const std::vector<double>& sliceBound = f.sliceBound;
    const Traversal& trav = f.trav;
    const bool earlyTermination = f.earlyTermination, xray = f.xray, descending = f.descending, ftb = f.ftb;
    const bool reversed = f.reversed, sheets = f.sheets;
    const int variant = f.variant, refresh = f.refresh;
    const GLuint p = f.program;
    const int guardInt = int(f.guard);
    const float zero[4] = {0, 0, 0, 0};
    const double diagonal = std::hypot(double(plane.width), double(plane.height));
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
        for (uint32_t k = k0; k < k1 && !g.stopHere(); ++k) {
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
    if (reversed) {
        // Front to back "under" (src (1 - dst.a) + dst), in groups of `refresh` slices.
        glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_FALSE);
        auto sliceAt = [&](uint32_t k) { return descending ? k : slices - 1 - k; };   // BTF's reverse
        for (uint32_t k0 = 0; k0 < slices && !g.stopHere(); k0 += uint32_t(refresh)) {
            const uint32_t k1 = std::min(slices, k0 + uint32_t(refresh));
            bool any = false;
            for (uint32_t k = k0; k < k1 && !any; ++k) any = sliceCommands(sliceAt(k)).second > 0;
            if (!any) continue;
            if (k0 > 0) g.maskOpaquePixels(f, g.depthFbo, true);
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
        const double hugeFootprint = settings.maxFootprintFraction > 0.0 ? settings.maxFootprintFraction * diagonal
                                                                         : std::numeric_limits<double>::infinity();
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
        for (uint32_t k = 0; k < slices && !g.stopHere(); ++k) {
            const uint32_t slice = descending ? slices - 1 - k : k;
            stale = stale || (earlyTermination && k > 0 && k % uint32_t(refresh) == 0);
            for (; occlusion && k == chunkEnd; chunkEnd += chunk) {
                if (drawnSinceMap) {
                    g.maskOpaquePixels(f, g.sheetFbo, true);
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
            ++stats.slicesDrawn;
            const Rect rect = sliceRect(g.origin, g.spacing, plane, trav.axis, int(slice), lo, hi,
                                        std::min(sliceBound[slice], hugeFootprint));
            // A slice off the image draws nothing; with counters it is drawn under an empty scissor all
            // the same, so its splats pass the guards and are counted as the CPU oracle counts them.
            const bool offImage = rect.x0 >= rect.x1 || rect.y0 >= rect.y1;
            if (offImage && !settings.counters) continue;
            if (stale) g.maskOpaquePixels(f, g.sheetFbo, false);   // mark what earlier slices made opaque
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
}

} // namespace renderer
