// Image-aligned slabs (renderer/oracle/image_slabs.h) with their pixel work on the GPU: the CPU prepares
// each kernel's footprint and depth law (slab_setup.h, the oracle's own code) and lists the kernels of
// each 8x8 tile in slab order; one compute invocation a pixel then sums the slabs' shares, classifies and
// lights them and composites front to back (renderer/shaders/slab_composite.comp). The near layer is
// composited on the CPU as the oracle does. Pre- and post-classified, shaded or not, perspective or
// orthographic; it agrees with renderImageAlignedSlabs to float rounding (tests/gl/test_image_slabs_gl.cpp).
//
// A first GL path, not yet a fast one: the per-kernel set-up runs on the CPU in double precision each
// frame, and the pass makes its buffers each frame. Needs a current GL 4.5 context.
#pragma once
#include "renderer/oracle/image_slabs.h"

#include <functional>

namespace renderer {

// Bytes of the slabs every pixel holds open at once (5 floats a slab; a pixel holds as many as one
// kernel reaches): a view that needs more is refused by name (take thicker slabs).
constexpr double kGlSlabRingBudget = 1024.0 * 1024.0 * 1024.0;

class ImageSlabsGl {
public:
    ImageSlabsGl();   // builds the pass's program and measures the driver's loop limit (GlError)
    ~ImageSlabsGl();
    ImageSlabsGl(const ImageSlabsGl&) = delete;
    ImageSlabsGl& operator=(const ImageSlabsGl&) = delete;

    // Throws RenderError as renderImageAlignedSlabs does, and beyond kGlSlabRingBudget.
    Image render(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                 const SlabOptions& options, SlabCounters* counters = nullptr) const;

    // Asked during the set-up and after each band of 8 tile rows of a dispatch (each band then waits for
    // the GPU: a whole post-classified dispatch took seconds on llvmpipe): once it returns true
    // render() throws Cancelled. An editor's newer view supersedes a slab frame this way.
    void setInterrupt(std::function<bool()> interrupted) { m_interrupt = std::move(interrupted); }

private:
    Image renderPlane(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& settings,
                      const SlabOptions& options, SlabCounters* counters) const;
    unsigned int m_program = 0;
    uint32_t m_loopLimit = 0;   // iterations the driver lets a shader's loops run (0: no limit)
    std::function<bool()> m_interrupt;
};

} // namespace renderer
