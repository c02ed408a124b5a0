// Tiled splatting, pass 4 (composite): a workgroup per tile blends its list into the image.
// One workgroup per tile, one invocation per pixel column: slice by slice, each of the column's pixels
// adds its splats into its sheet, which is composited into the pixel (front to back "under", back to
// front "over"; X-ray: summed and resolved at the end). Early termination as the rasterised sheets: a
// pixel whose alpha reached uOpaqueAlpha at a refresh (every uRefresh ranks) takes nothing more.
// A column per invocation fetches each record once for eight pixels (fetches were 60 % of a frame on
// llvmpipe with a pixel per invocation). Every row is evaluated without a branch: the cutoff test
// zeroes rows outside the ellipse, which lies inside the box the tiles were chosen by, and on llvmpipe
// a masked branch costs more than the row (both sides run under a mask). Whole slices and tiles are
// skipped by loops of at most one pass (SKIP_UNLESS): llvmpipe leaves a loop once no lane is in it.
// Such a loop costs more than a row's composite, so an empty sheet is composited too (it adds nothing).
#include "tile_state.glsl"
#include "shading.glsl"
#include "conic_form.glsl"
#include "tile_sheet.glsl"
#if SPLAT_TILE != 8
#error the row macros below assume 8x8 tiles
#endif
#define ROWS(X) X(0) X(1) X(2) X(3) X(4) X(5) X(6) X(7)
#define SKIP_UNLESS(cond) for (int once = 0; once < ((cond) ? 1 : 0); ++once)
layout(local_size_x = SPLAT_TILE) in;
// The list through texel fetches: llvmpipe gathers those without a bounds check per lane.
layout(binding = 0) uniform samplerBuffer entries;
layout(binding = 1) uniform samplerBuffer lut;   // without SPLAT_SHADING: the colour by LUT class
layout(std430, binding = 8) readonly buffer Bins { uint bins[]; };   // where each rank ends in its tile's list
// The image and heatmap so far (earlier chunks; cleared before the first), rows bottom up.
layout(rgba32f, binding = 0) uniform image2D outImage;
layout(rgba32f, binding = 1) uniform image2D outHeat;
layout(std430, binding = 11) writeonly buffer OpaqueTiles { uint opaqueTiles[]; };   // OCCLUSION
layout(std430, binding = 12) readonly buffer Busy { uvec4 busyGroups; uint busyTiles[]; };   // the tiles to do
shared uint liveColumns;
uniform ivec2 uTiles;
uniform int uRank0, uRanks, uRefresh;   // the chunk's ranks, as the count pass
uniform vec2 uViewport, uCentrePx;
uniform float uCutoff, uFPx, uOpaqueAlpha;
uniform bool uFrontToBack, uOrtho;
uniform ShadingParams uShadingParams;

vec4 composite(vec4 image, vec4 sheet) { return compositeSheet(image, sheet, uFrontToBack); }

#ifdef HEATMAP
#define ADD_HEAT(r) sheetHeat##r += vec4(mode == 0u ? tau : 0.0, mode == 1u ? tau : 0.0, mode == 2u ? tau : 0.0, tau);
#define COMPOSITE_HEAT(r) heat##r = composite(heat##r, sheetHeat##r);
#define STORE_HEAT(r) imageStore(outHeat, ivec2(px, int(uViewport.y) - 1 - (y0 + r)), heat##r);
#define LOAD_HEAT(r) imageLoad(outHeat, ivec2(px, int(uViewport.y) - 1 - (y0 + r)))
#else
#define LOAD_HEAT(r) vec4(0.0)
#define ADD_HEAT(r)
#define COMPOSITE_HEAT(r)
#define STORE_HEAT(r)
#endif
#ifdef FRAGMENT_SHADING   // towards the eye along this pixel's ray, taken once a pixel
#define DECLARE_VIEW(r) vec3 view##r = unitOrZero(toEyeAt(vec2(cx, float(y0 + r) + 0.5), uCentrePx, uFPx, uOrtho));
#define SHADE(r) vec3 colour = shadeUnit(c, normal, trust, view##r, uShadingParams);
#else
#define DECLARE_VIEW(r)
#define SHADE(r) vec3 colour = c;
#endif

// Past the image's edge imageLoad gives 0 (nothing is stored there).
#define DECLARE(r) \
    vec4 image##r = imageLoad(outImage, ivec2(px, int(uViewport.y) - 1 - (y0 + r))), heat##r = LOAD_HEAT(r), sheet##r, sheetHeat##r; \
    bool live##r = true; \
    DECLARE_VIEW(r)
#define REFRESH(r) live##r = image##r.a < uOpaqueAlpha;
#define CLEAR(r) sheet##r = vec4(0.0); sheetHeat##r = vec4(0.0);
// The Gaussian down a column. COLUMN_RECURRENCE: by recurrence, two sums and two products a row instead of
// the quadratic form and an exp (the exp was 12 % of the composite on llvmpipe, the form another 13 %). Along
// the column e(r+1) - e(r) = 2 b dx + c (2 dy + 1) grows by 2 c a row, so e takes two sums, and
// g(r+1) = g(r) h(r) with h(r) = exp(-(e(r+1) - e(r)) / 2), h(r+1) = h(r) exp(-c). The host sets it only where every
// footprint holds the 1-px low-pass (M >= I, so the conic's c <= 1: footprintsHoldThePixel) and the cutoff
// is at most 3 sigmas (columnRecurrence()): a column with a row inside the cutoff ellipse then has
// e <= (3 + 7)^2 = 100 in every row, so no factor under- or overflows; a column with none takes nothing,
// whatever its products.
#ifdef COLUMN_RECURRENCE
#define COLUMN_START \
    float dy0 = float(y0) + 0.5 - centre.y; \
    float e = conicForm(conic, dx, dy0), de = 2.0 * (conic.y * dx + conic.z * (dy0 + 0.5)), dde = 2.0 * conic.z; \
    float g = amplitude * exp(-0.5 * e); \
    float h = exp(-0.5 * de), k = exp(-conic.z);
#define EXPONENT(r) e
#define GAUSSIAN(e) g
#define COLUMN_STEP g *= h; h *= k; e += de; de += dde;
#else
#define COLUMN_START
#define EXPONENT(r) conicForm(conic, dx, float(y0 + r) + 0.5 - centre.y)
#define GAUSSIAN(e) amplitude * exp(-0.5 * (e))
#define COLUMN_STEP
#endif
#define ROW(r) { \
        float e##r = EXPONENT(r); \
        float tau = live##r && e##r <= cutoff2 ? GAUSSIAN(e##r) : 0.0; \
        COLUMN_STEP \
        SHADE(r) \
        sheet##r += vec4(colour * tau, tau); \
        ADD_HEAT(r) \
    }
#define COMPOSITE(r) { image##r = composite(image##r, sheet##r); COMPOSITE_HEAT(r) }
#define STORE(r) \
    if (y0 + r < int(uViewport.y)) { \
        imageStore(outImage, ivec2(px, int(uViewport.y) - 1 - (y0 + r)), image##r); \
        STORE_HEAT(r) \
    }

#define OPAQUE(r) && (y0 + r >= int(uViewport.y) || image##r.a >= uOpaqueAlpha)

void main() {
    // Only tiles with entries in this chunk: the others stay as they are.
    uint busy = gl_WorkGroupID.y * BUSY_ROW + gl_WorkGroupID.x;
    if (busy >= busyGroups.w) return;
    int t = int(busyTiles[busy]);
    int px = (t % uTiles.x) * SPLAT_TILE + int(gl_LocalInvocationID.x), y0 = (t / uTiles.x) * SPLAT_TILE;
    float cx = float(px) + 0.5;   // pixel centres, y down
    float cutoff2 = uCutoff * uCutoff;
    ROWS(DECLARE)
    uint base = tileBase[t], start = 0u;
    bool stale = false;   // a refresh is due before the next slice with splats here
    for (int k = 0; k < uRanks; ++k) {
        uint end = bins[t * uRanks + k];
        stale = stale || (uFrontToBack && (uRank0 + k) % uRefresh == 0);
        SKIP_UNLESS(end > start) {
            if (stale) { ROWS(REFRESH) }
            stale = false;
            bool anyLive = live0 || live1 || live2 || live3 || live4 || live5 || live6 || live7;
            ROWS(CLEAR)
            for (uint j = start; j < (anyLive ? end : start); ++j) {
                int i = int(ENTRY_TEXELS * (base + j));
                vec4 a = texelFetch(entries, i), b = texelFetch(entries, i + 1);
                vec2 centre = a.xy;
                vec3 conic = vec3(a.zw, b.x);
                float amplitude = b.y;
                uint bits = floatBitsToUint(b.z), mode = (bits >> 16) & 3u;
#ifdef SPLAT_SHADING
                vec3 c = texelFetch(entries, i + 2).rgb;
#else
                vec3 c = texelFetch(lut, int(bits >> 18)).rgb;
#endif
#ifdef FRAGMENT_SHADING
                vec3 gradient = texelFetch(entries, i + 2).xyz;
                vec3 normal = unitOrZero(gradient);
                float trust = normalTrust(gradient, uShadingParams);
#endif
                float dx = cx - centre.x;
                COLUMN_START
                ROWS(ROW)
            }
            ROWS(COMPOSITE)
        }
        start = end;
    }
#ifdef OCCLUSION   // the opaque-tile map the next chunk is binned against (pixels past the edge count as opaque)
    if (gl_LocalInvocationID.x == 0u) liveColumns = 0u;
    barrier();
    bool opaque = px >= int(uViewport.x) || (true ROWS(OPAQUE));
    if (!opaque) atomicOr(liveColumns, 1u);
    barrier();
    if (gl_LocalInvocationID.x == 0u) {
        opaqueTiles[t] = liveColumns == 0u ? 1u : 0u;
        if (liveColumns == 0u) opaqueTiles[uTiles.x * uTiles.y] = 1u;   // after the map: any tile opaque
    }
#endif
    if (px >= int(uViewport.x)) return;
    ROWS(STORE)
}
