// Reading the opaque-tile map (1 where every pixel of the tile is opaque) for occlusion culling, through
// texel fetches (Gl::bindCullMap): llvmpipe loads from a storage buffer lane by lane.
#ifdef OCCLUSION
layout(binding = 7) uniform usamplerBuffer opaqueTexels;
bool tileOpaque(int t) { return texelFetch(opaqueTexels, t).r != 0u; }
#endif
