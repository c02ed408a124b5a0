// Bucket selection: one indirect draw per run of the frame's axis, in the frame's order; inactive
// buckets draw 0 vertices. Runs only change with the volume, so a TF edit re-runs this pass and uploads
// nothing; so does a turn to another axis or order (one array, not one per order). Two layouts, since
// a frame may draw some slices as points and others as quads: the first uRuns commands draw a vertex
// a splat, the next uRuns six (32 bytes a run).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Runs { uvec4 runs[]; };     // first entry, tile, slice|bucket|dense, count
layout(std430, binding = 1) readonly buffer LutBuffer { vec4 lut[]; };
layout(std430, binding = 2) readonly buffer SliceRuns { uint sliceRuns[]; };   // as AxisLists::sliceRuns
layout(std430, binding = 3) writeonly buffer Commands { uvec4 commands[]; };
uniform uint uRuns;
uniform bool uAllBuckets;
uniform bool uDescending;   // slices from the highest, each slice's runs in their own order
uniform bool uReversed;     // the exact reverse (front-to-back splat-every-sample reverses each run too)
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uRuns) return;
    uvec4 run = runs[i];
    uint bucket = (run.z >> 16) & 0xffu;
    bool selected = uAllBuckets;
    for (uint c = bucket << 6; c < ((bucket + 1u) << 6) && !selected; ++c) selected = lut[c].a > 0.0;
    uint slice = run.z & 0xffffu;
    uint slot = uDescending ? uRuns - sliceRuns[slice + 1u] + (i - sliceRuns[slice]) : i;
    // DrawArraysIndirectCommand: count, instanceCount, first, baseInstance (selects this run's aRun). First
    // is 0: gl_VertexID counts within the run (splat.vert adds the run's first entry), so it stays under
    // 6 x 65536 whatever the volume's size, where 6 x the first entry overflowed an int from 358 M voxels.
    uint at = uReversed ? uRuns - 1u - slot : slot, count = selected ? run.w : 0u;
    commands[at] = uvec4(count, 1u, 0u, i);
    commands[uRuns + at] = uvec4(6u * count, 1u, 0u, i);
}
