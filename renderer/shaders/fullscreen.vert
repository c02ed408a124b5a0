// One triangle over the whole viewport, from gl_VertexID alone (no vertex buffer): the vertex stage of
// the full-screen passes (sheet composite, opaque mask, X-ray resolve, display).
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
