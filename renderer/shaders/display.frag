// Display: composite over the background and flip, so memory row 0 is the image's top row.
layout(binding = 0) uniform sampler2D image;
uniform vec3 uBackground;
out vec4 fragColour;
void main() {
    ivec2 size = textureSize(image, 0);
    vec4 c = texelFetch(image, ivec2(gl_FragCoord.x, size.y - 1 - int(gl_FragCoord.y)), 0);
    fragColour = vec4(c.rgb + (1.0 - c.a) * uBackground, 1.0);
}
