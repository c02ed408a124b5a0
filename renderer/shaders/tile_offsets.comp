// Tiled splatting, pass 2a (offsets): per tile, its counts per rank become offsets.
// Counts to offsets: per tile over its ranks (bins become where each rank starts in the tile's list,
// tileBase the tile's total); tile_bases.comp then goes over the tiles.
#include "tile_state.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 8) buffer Bins { uint bins[]; };
uniform int uTileCount, uRanks;
void main() {
    int t = int(gl_GlobalInvocationID.x);
    if (t >= uTileCount) return;
    uint sum = 0u;
    for (int k = 0; k < uRanks; ++k) {
        uint c = bins[t * uRanks + k];
        bins[t * uRanks + k] = sum;
        sum += c;
    }
    tileBase[t] = sum;
}
