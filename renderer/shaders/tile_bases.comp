// Tiled splatting, pass 2b (bases): where each tile's list starts, and the tiles with entries.
// After tile_offsets.comp, over the tiles, in one workgroup: tileBase becomes where each tile's list
// starts, entryCount the total; the tiles with entries are listed, with the composite's indirect
// dispatch (a grid BUSY_ROW wide: a dimension may be capped at 65535) and their count; the scatter's
// indirect dispatch; and the frame's figures a GPU reads only once the frame has finished
// (DriverProfile::deferredListChecks, frame_status.cpp).
#include "tile_state.glsl"
layout(local_size_x = 1024) in;
layout(std430, binding = 12) writeonly buffer Busy { uvec4 busyGroups; uint busyTiles[]; };
layout(std430, binding = 13) buffer FrameStatus {
    uint mostEntries;   // the most list entries a part took
    uint allEntries;    // the frame's entries (FrameStats::tileEntries)
    uint mostLoops;     // the most loop trips a tile's composite took
    uint anyCut;        // a record invocation was cut short (llvmpipe's loop limit)
};
layout(std430, binding = 14) writeonly buffer ScatterArgs { uvec4 scatterGroups; };
uniform int uTileCount;
uniform uint uLoopExtra;   // the composite's loop trips beyond the busiest tile's entries (the ranks')
uniform bool uBatches;     // the pixel layout also loops over the busiest tile's batches of 64
shared uint partial[1024], partialBusy[1024], partialMost[1024];
void main() {
    uint id = gl_LocalInvocationID.x;
    uint per = (uint(uTileCount) + 1023u) / 1024u;
    uint i0 = min(id * per, uint(uTileCount)), i1 = min(i0 + per, uint(uTileCount));
    uint sum = 0u, busy = 0u, most = 0u;
    for (uint i = i0; i < i1; ++i) {
        uint c = tileBase[i];
        sum += c;
        busy += c > 0u ? 1u : 0u;
        most = max(most, c);
    }
    partial[id] = sum;
    partialBusy[id] = busy;
    partialMost[id] = most;
    barrier();
    if (id == 0u) {
        uint running = 0u, runningBusy = 0u, runningMost = 0u;
        for (uint j = 0u; j < 1024u; ++j) {
            uint v = partial[j], b = partialBusy[j];
            partial[j] = running;
            partialBusy[j] = runningBusy;
            running += v;
            runningBusy += b;
            runningMost = max(runningMost, partialMost[j]);
        }
        entryCount = running;
        tileMost = runningMost;
        busyGroups = uvec4(min(runningBusy, BUSY_ROW), (runningBusy + BUSY_ROW - 1u) / BUSY_ROW, 1u, runningBusy);
        scatterGroups = uvec4(clamp((splatCount + 63u) / 64u, 1u, 65535u), 1u, 1u, 0u);
        mostEntries = max(mostEntries, running);
        allEntries += running;
        mostLoops = max(mostLoops, runningMost + (uBatches ? runningMost / 64u : 0u) + uLoopExtra);
        anyCut |= cut;
    }
    barrier();
    uint running = partial[id], runningBusy = partialBusy[id];
    for (uint i = i0; i < i1; ++i) {
        uint v = tileBase[i];
        tileBase[i] = running;
        running += v;
        if (v > 0u) busyTiles[runningBusy++] = i;
    }
}
