// The near layer of one pixel (near_layer.h; nearLayerSums() on the CPU, here in float): its centre ray
// from the eye, from the near plane on, through each near kernel as a 1D Gaussian on an interval, the
// kernel's optical depth in closed form (erf), summed per sheet. Out: the front sheet over the back one,
// premultiplied, blended over the image
// (GL_ONE, GL_ONE_MINUS_SRC_ALPHA); X-ray: 1 - exp(-sums), blended onto the resolved sums
// (GL_ONE, GL_ONE_MINUS_SRC_COLOR: 1 - (1 - a)(1 - b) = 1 - exp(-(A + B))).
#include "erf.glsl"
layout(std430, binding = 5) readonly buffer NearKernels {
    uint count;
    uint pad0, pad1, pad2;
    vec4 kernels[];   // two a kernel: (camera-space centre, extinction), (colour, 0 front sheet or 1 back)
};
uniform vec2 uCentrePx;
uniform float uFPx, uNear;
uniform float uHeight;      // image rows: gl_FragCoord.y counts from the bottom row
uniform mat3 uInvVarCamera; // W diag(1 / sigma^2) W^T
uniform float uCut2;        // cutoff^2, in sigmas^2
uniform float uPeak;        // kernelPeak(): the truncated kernel of unit mass at its centre
uniform bool uXRay;
layout(location = 0) out vec4 outColour;


void main() {
    vec2 px = vec2(gl_FragCoord.x, uHeight - gl_FragCoord.y);   // the pixel centre, rows down
    vec3 dir = normalize(vec3((px - uCentrePx) / uFPx, 1.0));
    float start = uNear / dir.z;                                 // where the ray crosses the near plane
    vec3 sDir = uInvVarCamera * dir;
    float qa = dot(dir, sDir);
    float width = inversesqrt(qa);
    vec4 sums[2] = vec4[2](vec4(0.0), vec4(0.0));   // per sheet: (emission, optical depth)
    uint n = min(count, MAX_NEAR_KERNELS);
    for (uint k = 0u; k < n; ++k) {
        vec4 centre = kernels[2u * k];
        // q(s) = (s dir - u)^T S^-1 (s dir - u) = qa s^2 + 2 qb s + qc, as kernelAlongRay()
        vec3 o = -centre.xyz;
        float qb = dot(o, sDir), qc = dot(o, uInvVarCamera * o);
        float qMin = qc - qb * qb / qa;
        if (!(qMin < uCut2)) continue;
        float mid = -qb / qa, halfLength = sqrt((uCut2 - qMin) / qa);
        float s0 = max(start, mid - halfLength), s1 = mid + halfLength;
        if (!(s1 > s0)) continue;
        float scale = 0.70710678 / width;
        float along = uPeak * exp(-0.5 * qMin) * width * 1.25331414 *   // sqrt(pi / 2)
                      (erfApprox((s1 - mid) * scale) - erfApprox((s0 - mid) * scale));
        float tau = centre.w * along;
        vec4 colour = kernels[2u * k + 1u];
        sums[int(colour.w)] += vec4(colour.rgb * tau, tau);
    }
    if (uXRay) {
        outColour = vec4(1.0) - exp(-(sums[0] + sums[1]));
        return;
    }
    vec4 sheet[2];
    for (int i = 0; i < 2; ++i) {
        float alpha = 1.0 - exp(-sums[i].w);
        sheet[i] = sums[i].w > 0.0 ? vec4(sums[i].rgb / sums[i].w * alpha, alpha) : vec4(0.0);
    }
    outColour = sheet[0] + (1.0 - sheet[0].a) * sheet[1];   // front over back
}
