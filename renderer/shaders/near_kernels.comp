// The near layer's kernels (near_layer.h, SplatRenderer::Gl::drawNearLayer): each invocation tests voxels
// of the box around the eye as NearTest::accepts() does on the CPU, the depth test as the splat stage
// writes it (splat_footprint.glsl), so a kernel is splatted or in the layer, never both; it appends the
// accepted ones, at most MAX_NEAR_KERNELS, with their sheet (NearTest::front()), and counts them all.
#include "splat_common.glsl"
layout(local_size_x = 64) in;
layout(binding = 0) uniform usampler3D classes;      // per-voxel LUT class (R16UI)
layout(binding = 4) uniform samplerBuffer lutTexels;
layout(std430, binding = 5) buffer NearKernels {
    uint count;       // accepted, beyond MAX_NEAR_KERNELS too (those are dropped)
    uint pad0, pad1, pad2;
    vec4 kernels[];   // two a kernel: (camera-space centre, extinction), (colour, 0 front sheet or 1 back)
};
uniform ivec3 uBoxLo, uBoxSize;   // the candidate voxels (nearCandidates())
uniform mat3 uVarCamera;          // as the splat stage's
uniform float uCutoff;            // in sigmas
uniform float uNearReach;         // as the splat stage's
uniform float uRadius;            // cutoff x the largest sigma
uniform vec3 uSides[4];           // the frustum's side planes' unit normals (NearTest::sides)
uniform float uExtinctionPerOpacity;   // density / mean spacing (voxelExtinction())
// Gradient opacity (SplatScene::opacityOf): the factor by the voxel's magnitude byte, after the LUT's
// 4096 entries; 0 when the renderer has none (a uniform branch: few voxels come here).
uniform int uGradientOpacity;
uniform int uTf2d;   // the 2D TF: colour and opacity by the (value, magnitude) cell, after the factors
layout(std430, binding = 3) readonly buffer Gradients { uint gradients[]; };   // 3 bytes a voxel (shading.h)
void main() {
    uint n = uint(uBoxSize.x) * uint(uBoxSize.y) * uint(uBoxSize.z);
    for (uint i = gl_GlobalInvocationID.x; i < n; i += gl_NumWorkGroups.x * 64u) {
        ivec3 ijk = uBoxLo + ivec3(int(i % uint(uBoxSize.x)), int(i / uint(uBoxSize.x) % uint(uBoxSize.y)),
                                   int(i / (uint(uBoxSize.x) * uint(uBoxSize.y))));
        uint cls = texelFetch(classes, ijk, 0).r;
        vec4 tf = texelFetch(lutTexels, int(cls));
        if (uGradientOpacity != 0 || uTf2d != 0) {
            uint byte = 3u * (uint(ijk.x) + uint(uDims.x) * (uint(ijk.y) + uint(uDims.y) * uint(ijk.z)));
            uint shift = (byte & 3u) * 8u;
            uint texel = gradients[byte >> 2u] >> shift | (gradients[(byte >> 2u) + 1u] << (31u - shift)) << 1u;
            uint magnitudeByte = (texel >> 16u) & 0xffu;
            if (uTf2d != 0) tf = texelFetch(lutTexels, 4352 + int((cls >> 4) * 64u + (magnitudeByte >> 2)));
            else tf.a *= texelFetch(lutTexels, 4096 + int(magnitudeByte)).a;
        }
        if (!(tf.a > 0.0)) continue;
        vec3 u = uViewFromObject * (uSpacing * vec3(ijk)) + uTranslation;
        float sigmaU2 = sqrt(uVarCamera[2][2]);
        if (u.z - uNearReach * sigmaU2 > uNear || !(u.z + uCutoff * sigmaU2 > uNear)) continue;
        bool inside = true;
        for (int s = 0; s < 4; ++s) inside = inside && !(dot(uSides[s], u) > uRadius);
        if (!inside) continue;
        uint slot = atomicAdd(count, 1u);
        if (slot >= MAX_NEAR_KERNELS) continue;
        kernels[2u * slot] = vec4(u, tf.a * uExtinctionPerOpacity);
        kernels[2u * slot + 1u] = vec4(tf.rgb, u.z - uCutoff * sigmaU2 > uNear ? 1.0 : 0.0);
    }
}
