// The rasterised splat's fragment stage: the Gaussian at the pixel centre, as optical depth or alpha.
#include "shading.glsl"
#include "conic_form.glsl"
flat in vec2 vCentre;
flat in vec3 vConic;
flat in float vAmplitude;
flat in vec3 vColour;
flat in vec3 vHeat;
flat in vec4 vNormalTrust;
uniform vec2 uViewport, uCentrePx;
uniform float uCutoff, uFPx;
uniform bool uOrtho;
uniform ShadingParams uShadingParams;
uniform bool uAdditive;       // sheets and X-ray sum optical depth; splat-every-sample blends "over"
layout(location = 0) out vec4 fragColour;
#ifdef HEATMAP
layout(location = 1) out vec4 fragHeat;
#endif

void main() {
    vec2 d = vec2(gl_FragCoord.x, uViewport.y - gl_FragCoord.y) - vCentre;   // y down, like the CPU
    float e = conicForm(vConic, d.x, d.y);
    if (e > uCutoff * uCutoff) discard;
    float tau = vAmplitude * exp(-0.5 * e);
    // 1 - exp(-tau) loses all digits in float for tiny tau; the series is exact to 1e-10 there.
    float w = uAdditive ? tau : (tau < 1e-3 ? tau * (1.0 - 0.5 * tau) : 1.0 - exp(-tau));
    vec3 colour = vColour;
#ifdef FRAGMENT_SHADING   // towards the eye along this pixel's ray
    vec2 px = vec2(gl_FragCoord.x, uViewport.y - gl_FragCoord.y);
    colour = shadeUnit(vColour, vNormalTrust.xyz, vNormalTrust.w, unitOrZero(toEyeAt(px, uCentrePx, uFPx, uOrtho)),
                       uShadingParams);
#endif
    fragColour = vec4(colour * w, w);
#ifdef HEATMAP
    fragHeat = vec4(vHeat * w, w);
#endif
}
