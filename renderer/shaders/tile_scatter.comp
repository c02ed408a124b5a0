// Tiled splatting, pass 3 (scatter): each splat copied into the lists of the tiles it reaches.
// Each splat copies what the composite needs into the list of every tile its box reaches (bins: the
// cursor per rank; afterwards where each rank ends). Copies, not indices: a tile then reads its list in
// order, where records fetched by index miss the cache (a third of bonsai's composite time on llvmpipe).
// An entry is (centre, conic.xy), (conic.z, amplitude, bits) and, with shading, the shaded colour or the
// gradient: without SPLAT_SHADING the composite fetches the colour from the LUT by class, so an entry
// takes 7 stored floats instead of 12 (llvmpipe pays per stored component).
#include "tile_state.glsl"
#include "opaque_tiles_read.glsl"
layout(local_size_x = 64) in;
layout(binding = 6) uniform samplerBuffer splatTexels;
layout(binding = 5) uniform usamplerBuffer stateTexels;   // TileState as texels: tileBase[t] is texel 4 + t
layout(std430, binding = 8) buffer Bins { uint bins[]; };
layout(std430, binding = 10) writeonly buffer Entries { vec4 entries[]; };
uniform ivec2 uTiles;
uniform int uRanks;
uniform vec2 uViewport;
uniform uint uListCapacity;   // entries the lists' buffer holds
void scatter(uint i) {
    int r = int(RECORD_VEC4S * i);
    vec4 box = texelFetch(splatTexels, r), conic = texelFetch(splatTexels, r + 1);
#ifdef SPLAT_SHADING
    vec4 colour = texelFetch(splatTexels, r + 2);
    float bits = colour.w;
#else
    float bits = texelFetch(splatTexels, r + 2).w;
#endif
#ifdef FRAGMENT_SHADING
    vec3 gradient = texelFetch(splatTexels, r + 3).xyz;
#endif
    int rank = int(floatBitsToUint(bits) & 0xffffu);
    // The same box as the count pass: the same floats through the same formulas.
    ivec2 ta = max(ivec2(ceil(box.xy - box.zw - 0.5)), ivec2(0)) / SPLAT_TILE;
    ivec2 tb = min(ivec2(floor(box.xy + box.zw - 0.5)), ivec2(uViewport) - 1) / SPLAT_TILE;
    for (int ty = ta.y; ty <= tb.y; ++ty)
        for (int tx = ta.x; tx <= tb.x; ++tx) {
            int t = ty * uTiles.x + tx;
#ifdef OCCLUSION   // as the count pass
            if (tileOpaque(t)) continue;
#endif
            uint slot = texelFetch(stateTexels, 4 + t).r + atomicAdd(bins[t * uRanks + rank], 1u);
            // Only a GPU's lists, sized from earlier frames, can be too short; that frame is drawn again.
            if (slot >= uListCapacity) continue;
            uint e = ENTRY_TEXELS * slot;
            entries[e] = vec4(box.xy, conic.xy);
            entries[e + 1u].xyz = vec3(conic.zw, bits);
#ifdef SPLAT_SHADING
            entries[e + 2u].xyz = colour.rgb;
#endif
#ifdef FRAGMENT_SHADING
            entries[e + 2u].xyz = gradient;
#endif
        }
}
void main() {   // a grid of at most 65535 workgroups walks every splat
    for (uint i = gl_GlobalInvocationID.x; i < splatCount; i += gl_NumWorkGroups.x * 64u) scatter(i);
}
