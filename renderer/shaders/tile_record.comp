// Tiled splatting, pass 1 of 4 (record). Tiled splatting (SplatSettings::Primitive::Tiles), for sheet
// and X-ray compositing: compute passes instead of the rasteriser. (1) Each kept splat is written as a
// record and counted in every screen tile (SPLAT_TILE pixels square) its box reaches, per slice rank;
// (2) the counts become offsets, per tile over the ranks and then over the tiles; (3) each splat copies
// its record into its tiles' lists;
// (4) one workgroup per tile walks its list slice by slice, every pixel keeping its sheet and the image
// in registers. A pixel's sums do not depend on the order within a slice, so the lists need no sort.
// The slices go through these passes in chunks, the image carried from one to the next (X-ray's
// resolve follows the last). Front to back with early termination each chunk is binned against the
// tiles earlier chunks made opaque (OCCLUSION), so hidden splats cost no entries.
// Records are RECORD_VEC4S vec4s: centre and half extent; conic and amplitude; its bits (rank | mode << 16 |
// LUT class << 18, with TF_2D the 2D TF's cell, 14 bits) in .w of the third, whose .rgb holds the colour with
// SPLAT_SHADING; FRAGMENT_SHADING: the gradient. The bits are only ever copied as a float, never computed
// with, so any pattern (a denormal, with a cell's high bits a NaN) arrives intact. List entries are
// ENTRY_TEXELS vec4s (see tile_scatter.comp).
#include "tile_state.glsl"
#include "shading.glsl"
#include "splat_common.glsl"
#include "opaque_tiles_read.glsl"
#include "splat_footprint.glsl"
layout(local_size_x = RUN_LANES) in;
layout(std430, binding = 5) readonly buffer Runs { uvec4 runs[]; };
layout(std430, binding = 6) readonly buffer Commands { uvec4 commands[]; };   // count 0: no active bucket
layout(std430, binding = 7) writeonly buffer Splats { vec4 splats[]; };
layout(std430, binding = 8) buffer Bins { uint bins[]; };                     // per tile and chunk rank
uniform uint uRunFirst, uRuns, uGroupsX;   // the chunk's runs
uniform ivec2 uTiles;
uniform int uSlices, uRank0, uRanks;       // the chunk: ranks uRank0 .. uRank0 + uRanks - 1
uniform bool uRankDescending;   // rank 0 is the highest slice
uniform uint uSegments;         // workgroups a run's voxels are dealt to (gl_WorkGroupID.z)
uniform uint uProbe;            // 2: the trip count of the loop that ends main()

bool countingInvocation() { return true; }

void main() {
    uint r = uRunFirst + gl_WorkGroupID.y * uGroupsX + gl_WorkGroupID.x;
    if (r >= uRunFirst + uRuns || commands[r].x == 0u) return;
    uvec4 run = runs[r];
    int slice = int(run.z & 0xffffu);
    uint rank = uint((uRankDescending ? uSlices - 1 - slice : slice) - uRank0);
    for (uint k = gl_WorkGroupID.z * uint(RUN_LANES) + gl_LocalInvocationID.x; k < run.w;
         k += uint(RUN_LANES) * uSegments) {
        Footprint f;
        if (!footprint(run, k, f)) continue;
        count(6);
        count(7 + f.mode);
        uint i = atomicAdd(splatCount, 1u);
        // On llvmpipe a storage-buffer store costs a loop over the lanes per component: only what is used.
        float bits = uintBitsToFloat(rank | uint(f.mode) << 16 | f.lutClass << 18);
        splats[RECORD_VEC4S * i] = vec4(f.centre, f.halfExtent);
        splats[RECORD_VEC4S * i + 1] = vec4(f.conic, f.amplitude);
#ifdef SPLAT_SHADING
        splats[RECORD_VEC4S * i + 2] = vec4(f.colour, bits);
#else
        splats[RECORD_VEC4S * i + 2].w = bits;
#endif
#ifdef FRAGMENT_SHADING
        splats[RECORD_VEC4S * i + 3].xyz = f.gradient;
#endif
        ivec2 ta = max(boxLo(f), ivec2(0)) / SPLAT_TILE, tb = min(boxHi(f), ivec2(uViewport) - 1) / SPLAT_TILE;
        for (int ty = ta.y; ty <= tb.y; ++ty)
            for (int tx = ta.x; tx <= tb.x; ++tx) {
                int t = ty * uTiles.x + tx;
#ifdef OCCLUSION   // an opaque tile takes nothing more: no entry
                if (tileOpaque(t)) continue;
#endif
                atomicAdd(bins[t * uRanks + int(rank)], 1u);
            }
    }
    // llvmpipe ends every loop of an invocation once its loops have run 65535 iterations together, so a
    // long run (or huge boxes) would lose splats without a word. A loop of uProbe (2) iterations that
    // stops after one says so; the host then deals the runs to more workgroups.
    uint probe = 0u;
    for (uint i = 0u; i < uProbe; ++i) ++probe;
    if (probe < uProbe) atomicOr(cut, 1u);
}
