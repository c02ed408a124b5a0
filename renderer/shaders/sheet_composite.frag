// Sheet compositing: the slice's sheet as premultiplied colour, blended behind the image (front to
// back: src (1 - dst.a) + dst) or over it (back to front). HEATMAP: the heat sheet likewise.
layout(binding = 0) uniform sampler2D sheet;
layout(binding = 1) uniform sampler2D sheetHeat;
layout(location = 0) out vec4 outColour;
#ifdef HEATMAP
layout(location = 1) out vec4 outHeat;
#endif

// (sum c tau, sum tau) -> premultiplied colour of alpha 1 - exp(-sum tau).
vec4 sheetRgba(vec4 q) {
    if (!(q.a > 0.0)) return vec4(0.0);
    float a = q.a < 1e-3 ? q.a * (1.0 - 0.5 * q.a) : 1.0 - exp(-q.a);
    return vec4(q.rgb / q.a * a, a);
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    outColour = sheetRgba(texelFetch(sheet, p, 0));
#ifdef HEATMAP
    outHeat = sheetRgba(texelFetch(sheetHeat, p, 0));
#endif
}
