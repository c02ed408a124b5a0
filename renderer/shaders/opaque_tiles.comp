// The opaque-tile map occlusion culling reads: 1 where every pixel of the tile (rows top down, as
// the splats' pixel coordinates) reached uOpaqueAlpha; pixels past the image's edge count as opaque.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 2) uniform sampler2D image;
layout(std430, binding = 11) writeonly buffer OpaqueTiles { uint opaqueTiles[]; };
uniform float uOpaqueAlpha;
uniform ivec2 uTiles;
void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (t.x >= uTiles.x || t.y >= uTiles.y) return;
    ivec2 size = textureSize(image, 0);
    bool opaque = true;
    for (int y = t.y * OPAQUE_TILE; y < min((t.y + 1) * OPAQUE_TILE, size.y); ++y)
        for (int x = t.x * OPAQUE_TILE; x < min((t.x + 1) * OPAQUE_TILE, size.x); ++x)
            opaque = opaque && texelFetch(image, ivec2(x, size.y - 1 - y), 0).a >= uOpaqueAlpha;
    opaqueTiles[t.y * uTiles.x + t.x] = opaque ? 1u : 0u;
    if (opaque) opaqueTiles[uTiles.x * uTiles.y] = 1u;   // after the map: any tile opaque
}
