// What the tile passes of a part share: splats recorded, list entries, the most entries one tile has (the
// composite's loop over them), whether a record-pass invocation was cut short (llvmpipe's loop limit:
// the end of tile_record.comp), then each tile's count and later where its list starts.
layout(std430, binding = 9) buffer TileState { uint splatCount; uint entryCount; uint tileMost; uint cut; uint tileBase[]; };
