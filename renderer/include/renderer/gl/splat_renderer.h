// The GL splatting path. Retained mode: the voxel classes, the LUT and the bucketed slice lists live
// on the GPU; a frame uploads only a few uniforms, a compute pass turns the LUT into indirect draws of
// the active buckets, and the vertex stage (or, tiled, a compute pass) rebuilds each splat from its
// list entry. A TF edit uploads
// the LUT and nothing else. Needs a current GL 4.5 core context (HeadlessGl or the editor's window).
#pragma once
#include "renderer/io/image.h"
#include "renderer/oracle/reference_renderer.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace renderer {

// The passes a frame's GPU time is split into (FrameStats::passMs), from GL_TIMESTAMP queries at each
// pass's start. Splats: the rasterised splats (vertex stage, rasteriser, blending) or, tiled, the record
// pass; Composite: the sheets into the image, rasterised or tiled; Opaque: the rasterised front-to-back
// opaque mask and tile map.
enum class GpuPass { Select, Patches, Splats, Offsets, Scatter, Composite, Opaque, Resolve };
constexpr int kGpuPasses = 8;
const char* gpuPassName(GpuPass pass);

struct FrameStats {
    uint64_t frame = 0;          // renders so far: the number of the last one
    bool timed = false;          // the last render's GPU times will come (false: the ring held only
                                 // unfinished renders, as when a GPU runs several behind, so it was not timed)
    uint64_t gpuFrame = 0;       // the render gpuMs and passMs are of (0: none timed yet)
    double gpuMs = 0.0;          // GPU time of the last frame whose timer query is ready (ring, no stall)
    std::array<double, kGpuPasses> passMs{};   // that frame's GPU time per GpuPass, from its start to
                                               // the next pass's (0: the pass did not run)
    double cpuMs = 0.0;          // CPU time spent issuing the frame
    int firstUsePrograms = 0;    // shader programs the last render used for the first time: drivers compile
                                 // them then (llvmpipe: hundreds of ms), so its times include that
    int gpuFirstUsePrograms = 0; // the same for the render gpuMs is of (gpuFrame)
    uint64_t splatsDrawn = 0;    // voxels of the active buckets sent to the vertex stage
    uint64_t uploadBytes = 0;    // bytes uploaded to buffers and textures by the last call
    uint64_t frameUploadBytes = 0;   // by the last render and every call since the render before it
                                     // (a TF edit's LUT, a new scene): what the frame shown cost to upload
    int pointSlices = 0;         // rasterised: slices drawn as point sprites (their footprints fit)...
    int quadSlices = 0;          // ...and as two-triangle quads (the others)
    bool tiles = false;          // the frame was tiled splatting (compute passes, no rasteriser)
    int slicesDrawn = 0;         // sheet modes: slices with an active bucket (the rest are skipped)
    bool hasCounters = false;    // SplatSettings::counters was on: `counters` holds the GPU's counts
    SplatCounters counters;
    uint64_t fragments = 0;      // with counters: samples passed in the frame (GL_SAMPLES_PASSED; sheet
                                 // and resolve passes included, discarded and depth-failed ones not)
    uint64_t tileEntries = 0;    // tiled splatting: (splat, tile) pairs the composite pass walked (in a
                                 // GPU's profile known once the frame is read back or displayed, or
                                 // at once with counters)
    int tileListSplits = 0;      // tiled splatting: times a chunk (or a part) went again in fewer slices:
                                 // its lists did not fit (the texel buffer, or 256 MiB), or its busiest
                                 // tile took more entries than the driver's loop limit lets one walk
    int readBacks = 0;           // buffer reads that waited for the frame's own passes (a GPU drains its
                                 // queue at each): per part of a tiled frame on llvmpipe, none in a
                                 // GPU's profile (DriverProfile::deferredListChecks) without counters
                                 // or occlusion culling
    bool redone = false;         // a GPU's profile: the frame's lists, sized from earlier frames, were
                                 // too short, so it was drawn again the checked way before its image
                                 // was read or displayed
    FilterMode adaptiveAs = FilterMode::Adaptive;   // an adaptive frame whose view put every patch in one
                                                    // filter (uniformAdaptiveFilter): that filter drew it
};

// How the frame's splats reached pixels: "tiles", "point sprites", "quads" or, for a frame that mixed
// them, "points and quads (quads in 4 of 256 slices)".
std::string primitiveName(const FrameStats& f);
// "tile lists went again in fewer slices 2 times: ..." for a frame whose chunks went in parts, else "".
std::string tileSplitsText(const FrameStats& f);

class SplatRenderer {
public:
    SplatRenderer();
    ~SplatRenderer();
    SplatRenderer(const SplatRenderer&) = delete;
    SplatRenderer& operator=(const SplatRenderer&) = delete;

    // Uploads classes, LUT and the bucketed lists. After setTransferFunction(scene, ...) call
    // setLut(tfTables(scene)).
    // Throws RenderError("<volume>: needs N MiB of GPU memory, M MiB free") when the scene does not fit:
    // checked up front where the driver reports free memory (GL_NVX_gpu_memory_info, GL_ATI_meminfo) or
    // a limit is set, and after every allocation through GL_OUT_OF_MEMORY.
    void setScene(const SplatScene& scene);
    // Gradients computed after setScene(scene) (addGradients): uploads them and nothing else. Reads only
    // the scene's name, dims and gradients.
    void setGradients(const SplatScene& scene);
    // A TF edit: uploads the LUT and the gradient factors (SplatScene::gradientFactors; empty: none),
    // their bytes all a TF edit costs; the next frame re-selects buckets. The factors apply once the
    // scene's gradients are on the GPU (setScene or setGradients).
    void setLut(const TfTables& tables);
    // Renders into the internal RGBA32F target (resized to plane.width x plane.height).
    void render(const ImagePlane& plane, const SplatSettings& settings);
    // The last frame as premultiplied float RGBA, row 0 at the top (X-ray already resolved). In a GPU's
    // profile this is where a frame whose lists were too short is drawn again (FrameStats::redone), so
    // it may throw what render() throws in llvmpipe's (a tile too crowded for `--primitive tiles`).
    Image readback();
    // The last frame's filter-mode heatmap (rendered when SplatSettings::heatmap was on; see
    // renderReference for its meaning).
    Image readbackHeatmap();
    // The per-patch filter for this view (computed on the GPU; layout of patchModes() on the CPU).
    std::vector<uint8_t> patchModes(const ImagePlane& plane, const SplatSettings& settings);
    // The last frame (or its filter-mode heatmap, when that was rendered) composited over `background`
    // in an RGBA8 texture, for display (GL name). Memory row 0 is the image's top row, so
    // ImGui::Image's default uvs show it upright.
    unsigned displayTexture(const float background[3], bool heatmap = false);
    // Reads finished GPU timer queries without waiting (call once per UI frame); render() calls it too.
    void collectTimers();
    const FrameStats& stats() const { return m_stats; }
    // Bytes of GPU memory the scene holds (textures and buffers), for the bytes-per-voxel budget.
    uint64_t sceneBytes() const;
    // Bytes of GPU memory tiled frames hold beyond the scene: records, lists, bins and tile state, sized
    // for the largest chunk so far (they grow, never shrink).
    uint64_t workingBytes() const;
    // Caps the GPU memory setScene() may use, in bytes (0: no cap beyond what the driver reports). Keeps
    // room for other applications, and lets tests take the out-of-memory path without exhausting a GPU.
    void setMemoryLimit(uint64_t bytes);
    // Caps the texels a tiled frame's lists may take (0: GL_MAX_TEXTURE_BUFFER_SIZE alone), as a GPU
    // with a smaller limit would: auto then rasterises with tiles' semantics. For tests.
    void setTexelBufferLimit(uint64_t texels);
    // Slices a tiled frame bins at once where nothing is culled (back to front, X-ray, no early
    // termination; 0: this driver's choice, 16 on llvmpipe and 64 elsewhere). For tests, and to compare.
    void setListChunkSlices(uint32_t slices);
    // The tile composite's layout: a pixel per invocation (a GPU's, true) or a column of 8 (llvmpipe's);
    // the driver's profile chooses it (renderer/gl/driver_profile.h). To compare the two on one driver.
    void setCompositePerPixel(bool perPixel);
    // Whether tiled frames read nothing back while they run (a GPU's profile, true) or read each part's
    // list sizes (llvmpipe's); renderer/gl/driver_profile.h chooses. To compare the two on one driver.
    void setDeferredListChecks(bool deferred);
    // Asked between chunks of slices (tiled) and between slices (rasterised) while a frame is issued: once it
    // returns true the frame stops there, and render() throws Cancelled (the image is incomplete). An editor
    // drops a frame that a newer edit superseded this way. Empty: frames always finish.
    void setInterrupt(std::function<bool()> interrupted);

private:
    // One attempt at render(): the reason when only drawing it told that it cannot be drawn (one
    // slice's tile lists do not fit), else empty. `rasterise`: auto's sheets and X-ray without tiles.
    std::string drawFrame(const ImagePlane& plane, const SplatSettings& settings, bool rasterise);
    // Before the last frame's image is used: in a GPU's profile, its figures read (a wait the image's use
    // makes anyway) and, where its lists were too short, the frame drawn again the checked way.
    void settleFrame();

    struct Gl;
    std::unique_ptr<Gl> m_gl;
    FrameStats m_stats;
};

} // namespace renderer
