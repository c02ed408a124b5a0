// Tiled splatting, pass 4 (composite), shaped for a GPU: a workgroup per tile and an invocation per pixel
// (64, two 32-wide warps), where tile_composite.comp (llvmpipe's) runs a column per invocation, 8 a tile.
// Each slice's entries are staged in shared memory 64 at a time, one fetched by each invocation; then
// every pixel adds all of them into its sheet, which is composited into the pixel (front to back
// "under", back to front "over"; X-ray: summed and resolved at the end). Early termination as the
// rasterised sheets: a pixel whose alpha reached uOpaqueAlpha at a refresh (every uRefresh ranks)
// takes nothing more, and a slice is not staged once no pixel of the tile takes anything.
// Control flow around the barriers depends only on the tile, so it is uniform across the workgroup.
#include "tile_state.glsl"
#include "shading.glsl"
#include "conic_form.glsl"
#include "tile_sheet.glsl"
#define GROUP (SPLAT_TILE * SPLAT_TILE)
layout(local_size_x = SPLAT_TILE, local_size_y = SPLAT_TILE) in;
layout(binding = 0) uniform samplerBuffer entries;
layout(binding = 1) uniform samplerBuffer lut;   // without SPLAT_SHADING: the colour by LUT class
layout(std430, binding = 8) readonly buffer Bins { uint bins[]; };   // where each rank ends in its tile's list
// The image and heatmap so far (earlier chunks; cleared before the first), rows bottom up.
layout(rgba32f, binding = 0) uniform image2D outImage;
layout(rgba32f, binding = 1) uniform image2D outHeat;
layout(std430, binding = 11) writeonly buffer OpaqueTiles { uint opaqueTiles[]; };   // OCCLUSION
layout(std430, binding = 12) readonly buffer Busy { uvec4 busyGroups; uint busyTiles[]; };   // the tiles to do
uniform ivec2 uTiles;
uniform int uRank0, uRanks, uRefresh;   // the chunk's ranks, as the count pass
uniform vec2 uViewport, uCentrePx;
uniform float uCutoff, uFPx, uOpaqueAlpha;
uniform bool uFrontToBack, uOrtho;
uniform ShadingParams uShadingParams;

// One batch of entries: centre and conic, amplitude and the packed bits, the colour (by the LUT or
// the record's shading), and with FRAGMENT_SHADING the normal and how far to trust it.
shared vec4 stagedA[GROUP], stagedB[GROUP];
shared vec3 stagedColour[GROUP];
#ifdef FRAGMENT_SHADING
shared vec4 stagedNormal[GROUP];
#endif
shared uint liveCount;

void stage(uint slot, uint entry) {
    int i = int(ENTRY_TEXELS * entry);
    vec4 a = texelFetch(entries, i), b = texelFetch(entries, i + 1);
    stagedA[slot] = a;
    stagedB[slot] = b;
#ifdef SPLAT_SHADING
    stagedColour[slot] = texelFetch(entries, i + 2).rgb;
#else
    stagedColour[slot] = texelFetch(lut, int(floatBitsToUint(b.z) >> 18)).rgb;
#endif
#ifdef FRAGMENT_SHADING
    vec3 gradient = texelFetch(entries, i + 2).xyz;
    stagedNormal[slot] = vec4(unitOrZero(gradient), normalTrust(gradient, uShadingParams));
#endif
}

void main() {
    // Only tiles with entries in this chunk: the others stay as they are.
    uint busy = gl_WorkGroupID.y * BUSY_ROW + gl_WorkGroupID.x;
    if (busy >= busyGroups.w) return;
    int t = int(busyTiles[busy]);
    uint lane = gl_LocalInvocationIndex;
    ivec2 px = ivec2((t % uTiles.x) * SPLAT_TILE, (t / uTiles.x) * SPLAT_TILE) + ivec2(gl_LocalInvocationID.xy);
    bool inside = px.x < int(uViewport.x) && px.y < int(uViewport.y);
    ivec2 texel = ivec2(px.x, int(uViewport.y) - 1 - px.y);   // pixel centres y down, the image bottom up
    vec2 centrePx = vec2(px) + 0.5;
    float cutoff2 = uCutoff * uCutoff;
    vec4 image = inside ? imageLoad(outImage, texel) : vec4(0.0);
#ifdef HEATMAP
    vec4 heat = inside ? imageLoad(outHeat, texel) : vec4(0.0);
#endif
#ifdef FRAGMENT_SHADING   // towards the eye along this pixel's ray
    vec3 view = unitOrZero(toEyeAt(centrePx, uCentrePx, uFPx, uOrtho));
#endif
    bool live = inside, anyLive = true;
    uint base = tileBase[t], start = 0u;
    bool stale = false;   // a refresh is due before the next slice with splats here
    for (int k = 0; k < uRanks; ++k) {
        uint end = bins[t * uRanks + k];
        stale = stale || (uFrontToBack && (uRank0 + k) % uRefresh == 0);
        if (end > start) {
            if (stale) {   // which pixels still take splats, and whether any does
                live = inside && image.a < uOpaqueAlpha;
                if (lane == 0u) liveCount = 0u;
                barrier();
                if (live) atomicAdd(liveCount, 1u);
                barrier();
                anyLive = liveCount > 0u;
                barrier();   // every lane has read it before the next refresh clears it
            }
            stale = false;
            vec4 sheet = vec4(0.0);
#ifdef HEATMAP
            vec4 sheetHeat = vec4(0.0);
#endif
            for (uint first = start; first < (anyLive ? end : start); first += uint(GROUP)) {
                barrier();   // the batch before is used up
                if (first + lane < end) stage(lane, base + first + lane);
                barrier();
                uint count = min(uint(GROUP), end - first);
                for (uint j = 0u; j < (live ? count : 0u); ++j) {
                    vec4 a = stagedA[j], b = stagedB[j];
                    float e = conicForm(vec3(a.zw, b.x), centrePx.x - a.x, centrePx.y - a.y);
                    float tau = e <= cutoff2 ? b.y * exp(-0.5 * e) : 0.0;
                    vec3 colour = stagedColour[j];
#ifdef FRAGMENT_SHADING
                    colour = shadeUnit(colour, stagedNormal[j].xyz, stagedNormal[j].w, view, uShadingParams);
#endif
                    sheet += vec4(colour * tau, tau);
#ifdef HEATMAP
                    uint mode = (floatBitsToUint(b.z) >> 16) & 3u;
                    sheetHeat += vec4(mode == 0u ? tau : 0.0, mode == 1u ? tau : 0.0, mode == 2u ? tau : 0.0, tau);
#endif
                }
            }
            image = compositeSheet(image, sheet, uFrontToBack);
#ifdef HEATMAP
            heat = compositeSheet(heat, sheetHeat, uFrontToBack);
#endif
        }
        start = end;
    }
#ifdef OCCLUSION   // the opaque-tile map the next chunk is binned against (pixels past the edge count as opaque)
    if (lane == 0u) liveCount = 0u;
    barrier();
    if (inside && image.a < uOpaqueAlpha) atomicAdd(liveCount, 1u);
    barrier();
    if (lane == 0u) {
        opaqueTiles[t] = liveCount == 0u ? 1u : 0u;
        if (liveCount == 0u) opaqueTiles[uTiles.x * uTiles.y] = 1u;   // after the map: any tile opaque
    }
#endif
    if (!inside) return;
    imageStore(outImage, texel, image);
#ifdef HEATMAP
    imageStore(outHeat, texel, heat);
#endif
}
