// The rasterised splat's vertex stage: a point or a quad around one listed voxel's footprint.
#include "shading.glsl"
#include "splat_common.glsl"
#include "opaque_tiles_read.glsl"
#include "splat_footprint.glsl"
layout(location = 0) in uvec4 aRun;  // per draw (baseInstance): the run record
uniform bool uReverse;        // front-to-back splat-every-sample: each run read backwards
uniform int uVertsPerSplat;   // 1: point sprite, 6: two triangles
uniform float uGuardPx;       // the viewport reaches this far past the image (points clip by centre)

flat out vec2 vCentre;
flat out vec3 vConic;
flat out float vAmplitude;
flat out vec3 vColour;
flat out vec3 vHeat;          // one-hot filter mode
flat out vec4 vNormalTrust;   // per-fragment shading: the unit normal and how far it is trusted

bool countingInvocation() { return gl_VertexID % uVertsPerSplat == 0; }

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);   // culled unless a footprint is emitted below
    gl_PointSize = 1.0;
    // The splat's place in its run: gl_VertexID counts from 0 in every run (bucket_commands.comp), and the
    // footprint adds a listed run's first entry (a dense run walks its tile).
    uint k = uint(gl_VertexID) / uint(uVertsPerSplat);
    if (uReverse) k = aRun.w - 1u - k;
    Footprint f;
    if (!footprint(aRun, k, f)) return;
    count(6);
    count(7 + f.mode);
    vCentre = f.centre;
    vConic = f.conic;
    vAmplitude = f.amplitude;
    vNormalTrust = vec4(unitOrZero(f.gradient), normalTrust(f.gradient, uShadingParams));
    vColour = f.colour;
    vHeat = vec3(f.mode == 0 ? 1.0 : 0.0, f.mode == 1 ? 1.0 : 0.0, f.mode == 2 ? 1.0 : 0.0);
    // Half a pixel of margin against rounding: the fragment test, not the primitive, decides coverage
    // (a pixel centre on the box's edge would lie on the cutoff ellipse).
    vec2 p = f.centre;
    if (uVertsPerSplat == 1) gl_PointSize = 2.0 * max(f.halfExtent.x, f.halfExtent.y) + 1.0;
    else p += kCorners[gl_VertexID % 6] * (f.halfExtent + 0.5);
    vec2 span = uViewport + 2.0 * uGuardPx;
    gl_Position = vec4(2.0 * (p.x + uGuardPx) / span.x - 1.0, 1.0 - 2.0 * (p.y + uGuardPx) / span.y, 0.0, 1.0);
}
