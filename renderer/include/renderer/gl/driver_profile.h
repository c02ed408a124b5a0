#pragma once
// The parameters that depend on the kind of GL driver, each chosen from measurements on its own kind
// (docs/speed.md, "On a GPU"): a llvmpipe figure never sets a GPU's value, nor the reverse.
#include <cstdint>
#include <string_view>

namespace renderer {

struct DriverProfile {
    bool software = false; // Mesa's llvmpipe: the "GPU" is the CPU's cores
    // Invocations a run of voxels takes in the record pass. llvmpipe: one SIMD row (8 lanes of 256
    // bits) looping over the run, 5 % faster on bonsai than 64 (fewer idle rows, each started once);
    // a GPU keeps full warps.
    int runLanes = 64;
    // Slices tiled splatting bins at once where nothing is culled (back to front, X-ray, no early
    // termination). A GPU waits for each chunk's read-back, so it takes 64 (bonsai back to front: 126 MB
    // for its largest chunk against 255 MB for all slices at once, at the same speed). llvmpipe: 16,
    // whose smaller lists stay in cache: bonsai and engine 3-5 % faster than 64, headsq 2-14 %.
    uint32_t listChunkSlices = 64;
    // The default of SplatSettings::occlusionCulling where the user has not chosen. Culling needs
    // chunks of a few slices, each ending in a read-back: llvmpipe runs the passes on the CPU, where the
    // read costs nothing and culling pays (bonsai tiles 157 against 209 ms); a GPU drains its queue at
    // each one (bonsai at 1920x1080: 13.7 against 6.35 ms on an H200, 12.4 against 6.78 on an H100).
    bool occlusionCulling = false;
    // The tile composite's layout. llvmpipe: a column of 8 pixels per invocation, 8 a tile, each entry
    // fetched once a column. The other layout (tile_composite_pixels.comp) takes a pixel per invocation,
    // 64 a tile, with each batch of 64 entries staged in shared memory: one fetch per entry for the tile,
    // and no three-quarters-idle 32-wide warps. On llvmpipe it is 18-23x slower (a barrier switches
    // coroutines). No GPU was lent after it was written, so a GPU keeps the column layout it was
    // measured with until `scripts/gpu-bench`'s composite-pixels and composite-columns rows say
    // otherwise (docs/speed.md, "On a GPU").
    bool compositePerPixel = false;
    // Whether a tiled frame reads nothing back while it runs. llvmpipe reads each part's list sizes (a
    // few bytes: its "GPU" is the CPU, so the read costs no idle time) and sizes the lists exactly. A GPU
    // drains its queue at each read, so its lists take a capacity from earlier frames' high-water mark,
    // the scatter drops what does not fit, and the figures are read once the frame has finished
    // (frame_status.cpp): a frame whose lists were too short is drawn again, once, the checked way.
    bool deferredListChecks = true;
};

// The profile of the driver named by GL_RENDERER. SPLATLAB_DRIVER_PROFILE=llvmpipe or gpu forces one
// (tests take the GPU's on llvmpipe).
DriverProfile driverProfile(std::string_view glRenderer);

} // namespace renderer
