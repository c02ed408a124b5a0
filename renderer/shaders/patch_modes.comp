// The adaptive classifier once per patch (SplatRenderer::Gl::classifyPatches): each patch's filter into
// an R8UI 3D image, last frame's read back for hysteresis.
#include "splat_common.glsl"
layout(local_size_x = 64) in;
layout(r8ui, binding = 0) uniform uimage3D modes;   // last frame's in, this frame's out
uniform int uNa, uNb, uSlices;
uniform bool uHasPrevious;
void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= uSlices * uNb * uNa) return;
    ivec3 at = ivec3(i % uNa, i / uNa % uNb, i / (uNa * uNb));
    ivec3 ijk;
    ijk[uAxis] = at.z;
    ijk[(uAxis + 1) % 3] = at.x * uPatchSize;
    ijk[(uAxis + 2) % 3] = at.y * uPatchSize;
    int previous = uHasPrevious ? int(imageLoad(modes, at).r) : 3;
    imageStore(modes, at, uvec4(resolveFilter(ijk, previous)));
}
