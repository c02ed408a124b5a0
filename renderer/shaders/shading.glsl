// Shading and surface splats (renderer/math/shading.h): line for line with shading.cpp, in float.
// The C++ side's shadingGlsl() returns this file.
const float kMinFootprintVariancePx2 = 0.3;

struct ShadingParams {
    float ambient;
    float diffuse;
    float specular;
    float shininess;
    float flatGradient;
};

// |g| / maxMagnitude from the packed w byte as an RGBA8 (unorm) fetch returns it.
float gradientMagnitude(float unormW) { return unormW * unormW; }

// (normal, |g| / maxMagnitude) of a packed 24-bit texel: octahedral (u, v) unfolded and normalised.
vec4 unpackGradient(uint texel) {
    vec4 bytes = unpackSnorm4x8(texel);
    float a = unpackUnorm4x8(texel).z;
    vec3 n = vec3(bytes.xy, 1.0 - abs(bytes.x) - abs(bytes.y));
    float t = max(-n.z, 0.0);
    n.x += n.x >= 0.0 ? -t : t;
    n.y += n.y >= 0.0 ? -t : t;
    return vec4(a > 0.0 ? n / sqrt(dot(n, n)) : vec3(0.0), gradientMagnitude(a));
}

// Towards the eye along the ray through the pixel centre `px` (pixels, y down), in camera space: the
// view direction of per-fragment shading. centrePx and fPx are the image plane's.
vec3 toEyeAt(vec2 px, vec2 centrePx, float fPx, bool orthographic) {
    return orthographic ? vec3(0.0, 0.0, -1.0) : -vec3((px - centrePx) / fPx, 1.0);
}
vec3 unitOrZero(vec3 v) {
    float l = length(v);
    return l > 0.0 ? v / l : vec3(0.0);
}
// How far the normal is trusted: 0 without a gradient, 1 from flatGradient up.
float normalTrust(vec3 gradientCamera, ShadingParams params) {
    float r = length(gradientCamera);
    return r > 0.0 ? min(r / params.flatGradient, 1.0) : 0.0;
}
// shade() from the unit normal, its trust and the unit direction to the eye: the tiles' per-fragment
// composite takes the first two once an entry and the third once a pixel.
vec3 shadeUnit(vec3 colour, vec3 n, float trust, vec3 v, ShadingParams params) {
    float c = abs(dot(n, v));
    float rv = max(2.0 * c * c - 1.0, 0.0);
    vec3 phong = colour * (params.ambient + params.diffuse * c) +
                 vec3(params.specular * pow(rv, params.shininess));
    return colour + trust * (phong - colour);
}
vec3 shade(vec3 colour, vec3 gradientCamera, vec3 toEyeCamera, ShadingParams params) {
    return shadeUnit(colour, unitOrZero(gradientCamera), normalTrust(gradientCamera, params),
                     unitOrZero(toEyeCamera), params);
}

// flatten >= 1, validated by the caller (the C++ throws).
mat3 surfaceVarianceCamera(vec3 sigma, mat3 viewFromObject, vec3 normalObject, float flatten) {
    float len = length(normalObject);
    vec3 n = len > 0.0 && !isinf(len) ? normalObject / len : vec3(0.0);
    mat3 s = mat3(1.0) - (1.0 - 1.0 / flatten) * outerProduct(n, n);
    mat3 t = viewFromObject * s;
    vec3 v = sigma * sigma;
    return t * mat3(v.x, 0.0, 0.0, 0.0, v.y, 0.0, 0.0, 0.0, v.z) * transpose(t);
}

mat2 clampFootprintVariance(mat2 v, float minVariancePx2) {
    float a = v[0][0], c = v[1][1], b = 0.5 * (v[0][1] + v[1][0]);
    float m = 0.5 * (a + c), h = 0.5 * (a - c);
    float d = sqrt(h * h + b * b);
    float lo = m - d, hi = m + d;
    if (lo >= minVariancePx2) return v;
    if (hi <= minVariancePx2) return mat2(minVariancePx2);
    float t = (minVariancePx2 - lo) / (hi - lo);
    mat2 s = mat2(a, b, b, c);
    return s + t * (hi * mat2(1.0) - s);
}
