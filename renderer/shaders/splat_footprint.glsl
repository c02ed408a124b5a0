// The footprint of one listed voxel, shared by the vertex stage and the tile pass: the same guards in
// the same order, counted in the same slots. Needs shading.glsl, splat_common.glsl and
// opaque_tiles_read.glsl included before it.
layout(std430, binding = 0) readonly buffer Entries { uint entries[]; };   // 16-bit offsets, two a word
// The LUT through texel fetches: on llvmpipe a storage-buffer load of a vec4 cost a third of the footprint.
layout(binding = 4) uniform samplerBuffer lutTexels;
layout(std430, binding = 2) buffer Counters { uint counters[]; };
layout(std430, binding = 3) readonly buffer Gradients { uint gradients[]; };   // 3 bytes a voxel (shading.h)
// Adaptive: each patch's filter at (patch along a1, patch along a2, slice), written by the patch pass.
layout(binding = 8) uniform usampler3D patchModes;
uniform float uInvPatchSize;
layout(binding = 0) uniform usampler3D classes;      // per-voxel LUT class (R16UI)

uniform ShadingParams uShadingParams;
uniform float uSurfaceFlatten, uSurfaceGradient;   // flatten 1: no surface splats
uniform vec3 uSigma;          // kernel sigma per object axis

uniform vec2 uCentrePx, uViewport;
uniform mat3 uVarCamera;      // W V'' W^T, shared by every voxel of a rectilinear grid
uniform float uCutoff;        // in sigmas
uniform float uNearReach;     // sigmas along u2 a splatted kernel keeps from the near plane (splatNearReach())
uniform float uExtinctionScale;   // density / mean spacing * voxel volume / the footprint's mass within the cutoff
uniform float uMaxHalfExtent;     // huge-footprint guard, pixels (+inf: none, the default)

// Program variants (SplatRenderer::Gl::splatProgram) switch features with #defines: llvmpipe runs
// both sides of a branch under a mask, so an unused feature would still cost every vertex/fragment.
bool countingInvocation();
void count(int slot) {   // COUNTERS: count per splat (slots: CounterSlot)
#ifdef COUNTERS
    if (countingInvocation()) atomicAdd(counters[slot], 1u);
#endif
}

struct Footprint {
    vec2 centre, halfExtent;  // pixels, y down; the cutoff ellipse's box
    vec3 conic;               // (a, b, c): e = a dx^2 + 2 b dx dy + c dy^2
    float amplitude;          // optical depth at the centre
    vec3 colour;
    vec3 gradient;            // per-fragment shading: W times the decoded relative gradient
    int mode;                 // the filter used
    uint lutClass;            // tiles fetch the unshaded colour by it (TF_2D: the 2D TF's cell)
};

// The packed gradient of voxel ijk: its 3 bytes from the two words they may span (gradientBufferBytes()
// pads one word).
uint gradientTexel(ivec3 ijk) {
    uint voxel = uint(ijk.x) + uint(uDims.x) * (uint(ijk.y) + uint(uDims.y) * uint(ijk.z));
    uint byte = 3u * voxel, shift = (byte & 3u) * 8u;
    return gradients[byte >> 2u] >> shift | (gradients[(byte >> 2u) + 1u] << (31u - shift)) << 1u;
}

// Pixels the footprint can touch, as the CPU's box: centres inside centre -+ halfExtent.
ivec2 boxLo(Footprint f) { return ivec2(ceil(f.centre - f.halfExtent - 0.5)); }
ivec2 boxHi(Footprint f) { return ivec2(floor(f.centre + f.halfExtent - 0.5)); }

#ifdef OCCLUSION
uniform int uTilesX;          // columns of the opaque-tile map
// Culled when every tile under the pixels it can touch was opaque at the last snapshot of the map:
// early termination would reject each of its pixels anyway. Boxes wider than 4 tiles are kept.
bool hidden(Footprint f) {
    ivec2 ta = clamp(boxLo(f), ivec2(0), ivec2(uViewport) - 1) / OPAQUE_TILE;
    ivec2 tb = clamp(boxHi(f), ivec2(0), ivec2(uViewport) - 1) / OPAQUE_TILE;
    if (tb.x - ta.x >= 4 || tb.y - ta.y >= 4) return false;
    for (int ty = ta.y; ty <= tb.y; ++ty)
        for (int tx = ta.x; tx <= tb.x; ++tx)
            if (!tileOpaque(ty * uTilesX + tx)) return false;   // most splats leave at their first tile
    return true;
}
#endif

// Entry k of run `run` (first entry, tile base, slice | bucket << 16 | dense << 31, count): false when
// a guard culls it (counted in its slot).
bool footprint(uvec4 run, uint k, out Footprint f) {
    bool dense = (run.z >> 31) != 0u;
    uint e = run.x + k;
    uint pos = run.y + (dense ? k : (entries[e >> 1] >> ((e & 1u) * 16u)) & 0xffffu);
    int a1 = (uAxis + 1) % 3, a2 = (uAxis + 2) % 3;
    ivec3 ijk;
    ijk[uAxis] = int(run.z & 0xffffu);
    ijk[a1] = int(pos % uint(uDims[a1]));
    ijk[a2] = int(pos / uint(uDims[a1]));
    uint cls = texelFetch(classes, ijk, 0).r;
    if (dense && (cls >> 6) != ((run.z >> 16) & 0xffu)) return false;   // another bucket's voxel
    count(0);
#ifdef TF_2D   // colour and opacity by the (value, magnitude) cell, after the factors (SplatScene::tf2dCell)
    uint texel = gradientTexel(ijk);
    f.lutClass = (cls >> 4) * 64u + (((texel >> 16u) & 0xffu) >> 2);   // tiles fetch the colour by the cell
    vec4 tf = texelFetch(lutTexels, 4352 + int(f.lutClass));
#else
    f.lutClass = cls;
    vec4 tf = texelFetch(lutTexels, int(cls));
#endif
#ifdef GRADIENT_OPACITY   // the factor by the magnitude byte, after the LUT's 4096 entries (SplatScene::opacityOf)
    uint texel = gradientTexel(ijk);
    tf.a *= texelFetch(lutTexels, 4096 + int((texel >> 16u) & 0xffu)).a;
#endif
    if (!(tf.a > 0.0)) { count(1); return false; }

    vec3 u = uViewFromObject * (uSpacing * vec3(ijk)) + uTranslation;
    if (!(u.z > uNear)) { count(2); return false; }
    float l = length(u);
    float iz = 1.0 / u.z;
    // Pixel-unit Jacobian (001 eq. 25), written row by row, transposed into GLSL's column order;
    // orthographic: the constant affine map.
    mat3 J = uOrtho ? mat3(uFPx, 0.0, 0.0, 0.0, uFPx, 0.0, 0.0, 0.0, 1.0)
                    : transpose(mat3(uFPx * iz, 0.0, -uFPx * u.x * iz * iz,
                                     0.0, uFPx * iz, -uFPx * u.y * iz * iz,
                                     u.x / l, u.y / l, u.z / l));
#if defined(SURFACE) || defined(SPLAT_SHADING) || defined(FRAGMENT_SHADING)
#if !defined(GRADIENT_OPACITY) && !defined(TF_2D)   // read here, past the culls, when only shading needs it
    uint texel = gradientTexel(ijk);
#endif
    vec4 grad = unpackGradient(texel & 0xffffffu);
#else
    vec4 grad = vec4(0.0);
#endif
#ifdef SURFACE
    bool surface = grad.w >= uSurfaceGradient;
    mat3 varCamera = surface ? surfaceVarianceCamera(uSigma, uViewFromObject, grad.xyz, uSurfaceFlatten) : uVarCamera;
#else
    bool surface = false;
    mat3 varCamera = uVarCamera;
#endif
    // A kernel whose cutoff ellipsoid reaches the near plane is not splatted, nor one just behind it with a
    // near layer, as splatGeometry() on the CPU (the near layer takes them).
    if (!uOrtho && !(u.z - uNearReach * sqrt(varCamera[2][2]) > uNear)) { count(2); return false; }
    mat3 V = J * varCamera * transpose(J);
    mat2 vHat = mat2(V[0][0], V[0][1], V[1][0], V[1][1]);
#ifdef ADAPTIVE   // the patch's filter, classified once per patch by the patch pass
    // By float (exact: the half keeps a multiple of the size off the boundary): llvmpipe divides
    // integers lane by lane.
    int pa = int((float(ijk[a1]) + 0.5) * uInvPatchSize), pb = int((float(ijk[a2]) + 0.5) * uInvPatchSize);
    f.mode = int(texelFetch(patchModes, ivec3(pa, pb, ijk[uAxis]), 0).r);
#else
    f.mode = uFilter;
#endif
    mat2 M = f.mode == 0 ? vHat : (f.mode == 1 ? mat2(1.0) : vHat + mat2(1.0));
    if (surface && f.mode == 0) M = clampFootprintVariance(M, kMinFootprintVariancePx2);
    float det = M[0][0] * M[1][1] - M[0][1] * M[1][0];
    if (!(det > 1e-12)) { count(3); return false; }
    f.halfExtent = uCutoff * sqrt(vec2(M[0][0], M[1][1]));
    if (max(f.halfExtent.x, f.halfExtent.y) > uMaxHalfExtent) { count(4); return false; }
    f.centre = uCentrePx + uFPx * (uOrtho ? u.xy : u.xy * iz);
    if (f.centre.x + f.halfExtent.x < 0.0 || f.centre.x - f.halfExtent.x > uViewport.x ||
        f.centre.y + f.halfExtent.y < 0.0 || f.centre.y - f.halfExtent.y > uViewport.y) { count(5); return false; }
#ifdef OCCLUSION   // hidden: culled before its conic, amplitude and shading are computed
    if (hidden(f)) { count(10); return false; }
#endif

    float detJ = uOrtho ? uFPx * uFPx : uFPx * uFPx * l * iz * iz * iz;
    f.conic = vec3(M[1][1], -M[0][1], M[0][0]) / det;
    f.amplitude = tf.a * uExtinctionScale * detJ / (6.283185307 * sqrt(det));
    f.gradient = uViewFromObject * (grad.xyz * grad.w);
#ifdef SPLAT_SHADING
    f.colour = shade(tf.rgb, f.gradient, -u, uShadingParams);
#else
    f.colour = tf.rgb;
#endif
    return true;
}

