// Early termination, before each front-to-back slice: pixels of the image whose alpha reached
// uOpaqueAlpha get depth 0.5 in the sheet's depth buffer, where the splats (also at 0.5) then fail
// GL_LESS: no fill is spent behind opaque pixels.
layout(binding = 2) uniform sampler2D image;
uniform float uOpaqueAlpha;
void main() {
    if (texelFetch(image, ivec2(gl_FragCoord.xy), 0).a < uOpaqueAlpha) discard;
}
