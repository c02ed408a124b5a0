// X-ray resolve, in place: the accumulated sums become 1 - exp(-sum), like the CPU oracle; the
// heatmap splits that alpha by each mode's share of the sum.
layout(binding = 2) uniform sampler2D image;
layout(binding = 3) uniform sampler2D heat;
layout(location = 0) out vec4 outColour;
layout(location = 1) out vec4 outHeat;
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    outColour = vec4(1.0) - exp(-texelFetch(image, p, 0));
    vec4 h = texelFetch(heat, p, 0);
    float a = 1.0 - exp(-h.a);
    outHeat = vec4(h.a > 0.0 ? h.rgb * (a / h.a) : vec3(0.0), a);
}
