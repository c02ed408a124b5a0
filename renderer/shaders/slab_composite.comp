// Image-aligned slabs (renderer/oracle/image_slabs.h) on the GPU: an invocation per pixel walks its
// 8x8 tile's kernels in the order of the first slab each reaches (prepared on the CPU: slab_setup.h),
// adds each kernel's share of every slab it reaches at the pixel (erf of its conditional depth law
// along the ray) into a ring of the slabs still open, and composites a slab under the pixel once no
// later kernel can reach it, front to back with early termination: the oracle's loop, in float.
// A dispatch takes list entries [uEntry0, uEntry1) of every tile: llvmpipe ends a shader's loops after
// 65535 iterations in all, so a long list goes in several dispatches, each pixel's state (its image so
// far, its ring, the next slab to composite, its work) kept in buffers between them. Loops are few and
// short for that reason: the small ones are written out.
#include "shading.glsl"
#include "erf.glsl"
layout(local_size_x = 8, local_size_y = 8) in;

// A kernel: (centre px, conic xx, conic xy), (conic yy, amplitude, depth - first slab, depth deviation),
// the depth's slope per px, its first slab (from the frame's first) and how many it reaches, what it adds
// before the weight (pre-classified: colour; post-classified: value, gradient), and pre-classified
// per-fragment shading's gradient.
struct Kernel {
    vec4 a, b;
    vec2 slope;
    int first, count;
    vec4 d, e;
};
layout(std430, binding = 0) readonly buffer Kernels { Kernel kernels[]; };
layout(std430, binding = 1) readonly buffer TileStarts { uint tileStarts[]; };   // tiles + 1
layout(std430, binding = 2) readonly buffer TileKernels { uint tileKernels[]; };
layout(std430, binding = 3) readonly buffer Lut { vec4 lut[]; };
layout(std430, binding = 4) buffer Pixels { vec4 pixels[]; };   // premultiplied RGBA so far, rows down
// Per pixel: the first slab not yet composited, footprint pixels and slab writes so far.
layout(std430, binding = 5) buffer State { uvec4 states[]; };
// Each pixel's ring of open slabs, uRing * 5 floats a pixel: slab j's sums at (j % uRing) * 5, uStride of
// them, the weight last.
layout(std430, binding = 6) buffer Rings { float rings[]; };
uniform ivec2 uSize;
uniform int uTilesX, uRing, uStride, uLutSize;
uniform uint uEntry0, uEntry1;   // this dispatch's entries of each tile's list
uniform bool uFirst, uLast;      // the dispatch that starts the pixels, and the one that finishes them
uniform int uTileRow0;           // the first row of tiles this dispatch covers (a band: see image_slabs_gl.cpp)
uniform float uCut2, uOpaqueAlpha, uPerOpacity, uFPx;
uniform vec2 uCentrePx;
uniform bool uPost, uShaded, uPerFragment, uOrtho;
uniform ShadingParams uShadingParams;

// The LUT at a fractional class, linear between classes (post_classification.h's lutAt).
vec4 lutAt(float v) {
    v = clamp(isnan(v) ? 0.0 : v, 0.0, float(uLutSize - 1));
    int i = min(int(v), uLutSize - 2);
    return mix(lut[i], lut[i + 1], v - float(i));
}

// Slab j under the pixel (sheet_compositing.h's under; post-classified, classifyPost), then emptied.
void composite(int j, vec2 px, int ringBase, inout vec4 acc) {
    int o = ringBase + (j % uRing) * 5;
    float w = rings[o + uStride - 1];
    if (w > 0.0) {
        vec3 c;
        float a;
        if (uPost) {
            vec4 tf = lutAt(rings[o] / w);
            a = 1.0 - exp(-tf.a * uPerOpacity * w);
            c = tf.rgb;
            if (uShaded)
                c = shade(c, vec3(rings[o + 1], rings[o + 2], rings[o + 3]) / w, toEyeAt(px, uCentrePx, uFPx, uOrtho),
                          uShadingParams);
            c *= a;
        } else {
            a = 1.0 - exp(-w);
            c = vec3(rings[o], rings[o + 1], rings[o + 2]) / w * a;
        }
        acc.rgb += (1.0 - acc.a) * c;
        acc.a += (1.0 - acc.a) * a;
    }
    rings[o] = 0.0;
    rings[o + 1] = 0.0;
    rings[o + 2] = 0.0;
    rings[o + 3] = 0.0;
    rings[o + 4] = 0.0;
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, uTileRow0 * int(gl_WorkGroupSize.y));
    if (any(greaterThanEqual(p, uSize))) return;
    int at = p.y * uSize.x + p.x;
    int ringBase = at * uRing * 5;   // this pixel's ring in `rings`
    vec4 acc = vec4(0.0);
    uvec4 state = uvec4(0u);   // next slab, footprint pixels, slab writes
    if (uFirst) {
        for (int k = 0; k < uRing * 5; ++k) rings[ringBase + k] = 0.0;
    } else {
        acc = pixels[at];
        state = states[at];
    }
    int next = int(state.x);
    vec2 px = vec2(p) + 0.5;
    int tile = (p.y / 8) * uTilesX + p.x / 8;
    uint end = min(tileStarts[tile] + uEntry1, tileStarts[tile + 1]);
    // Once the pixel is opaque no kernel adds to it: what remains is the open slabs, composited below
    // in the order the oracle composites them as later kernels arrive.
    bool opaque = uOpaqueAlpha < 1.0 && acc.a >= uOpaqueAlpha;
    for (uint k = tileStarts[tile] + uEntry0; k < end && !opaque; ++k) {
        Kernel s = kernels[tileKernels[k]];
        int first = s.first, count = s.count;
        for (int j = next; j < first && j < next + uRing; ++j) composite(j, px, ringBase, acc);   // only these hold sums
        next = max(next, first);
        opaque = uOpaqueAlpha < 1.0 && acc.a >= uOpaqueAlpha;
        vec2 d = px - s.a.xy;
        float e = d.x * d.x * s.a.z + 2.0 * d.x * d.y * s.a.w + d.y * d.y * s.b.x;
        if (!opaque && e <= uCut2) {
            ++state.y;
            float tau = s.b.y * exp(-0.5 * e);
            vec4 adds = s.d;
            if (uPerFragment) adds.rgb = shade(s.d.rgb, s.e.xyz, toEyeAt(px, uCentrePx, uFPx, uOrtho), uShadingParams);
            float mean = s.b.z + dot(s.slope, d), sd = s.b.w;
            float below = 0.0;   // the law's probability before slab first + i
            for (int i = 0; i < count; ++i) {
                float upTo = 1.0;
                if (i + 1 < count)
                    upTo = sd > 0.0 ? 0.5 + 0.5 * erfApprox((float(i + 1) - mean) / (1.41421356 * sd))
                                    : (mean < float(i + 1) ? 1.0 : 0.0);
                float t = tau * (upTo - below);
                below = upTo;
                if (t > 0.0) {   // the sums in the layout of uStride
                    int o = ringBase + ((first + i) % uRing) * 5;
                    rings[o] += adds.x * t;
                    if (uStride >= 4) {
                        rings[o + 1] += adds.y * t;
                        rings[o + 2] += adds.z * t;
                    }
                    if (uStride == 5) rings[o + 3] += adds.w * t;
                    rings[o + uStride - 1] += t;
                    ++state.z;
                }
            }
        }
    }
    if (uLast || opaque)
        for (int j = next; j < next + uRing; ++j) composite(j, px, ringBase, acc);
    state.x = uint(next);
    pixels[at] = acc;
    states[at] = state;
}
