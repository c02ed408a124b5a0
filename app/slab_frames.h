// `render --image-slabs`: frames of image-aligned slabs on the CPU oracle (--cpu) or with their pixel
// work on the GPU (renderer/gl/image_slabs_gl.h), for timed frames and orbits alike.
#pragma once
#include "renderer/gl/gl_context.h"
#include "renderer/gl/image_slabs_gl.h"
#include "renderer/oracle/image_slabs.h"
#include "ui/editor_state.h"

#include <memory>
#include <optional>
#include <string>

class SlabFrames {
public:
    explicit SlabFrames(bool cpu);   // without --cpu: a headless GL context (GlError without one)
    renderer::Image render(const renderer::SplatScene& scene, const renderer::ImagePlane& plane,
                           const renderer::SplatSettings& settings, const renderer::SlabOptions& options,
                           renderer::SlabCounters* counters = nullptr) const;
    const std::string& device() const { return m_device; }   // "CPU oracle (double)" or GL_RENDERER

private:
    std::unique_ptr<renderer::HeadlessGl> m_context;
    std::unique_ptr<renderer::ImageSlabsGl> m_pass;
    std::string m_device;
};

// "image-aligned slabs 0.25 voxels thick, post-classified, 2x2 samples a pixel": what the frames composite.
std::string slabsText(const renderer::SlabOptions& options);

// The slabs a still view ends in (Settings > Image-aligned slabs), in the editor and in `render --session`:
// none when they are off, for X-ray (order-free: no slabs) or for surface splats (which they do not model).
std::optional<renderer::SlabOptions> slabsOfStillView(const ui::SlabView& slabs, const renderer::SplatSettings& s);
