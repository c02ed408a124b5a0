// Image-aligned slab frames on the CPU or the GPU (see slab_frames.h).
#include "slab_frames.h"

#include <cstdio>

SlabFrames::SlabFrames(bool cpu) : m_device("CPU oracle (double)") {
    if (cpu) return;
    m_context = renderer::HeadlessGl::create();
    m_pass = std::make_unique<renderer::ImageSlabsGl>();
    m_device = renderer::glRendererName();
}

renderer::Image SlabFrames::render(const renderer::SplatScene& scene, const renderer::ImagePlane& plane,
                                   const renderer::SplatSettings& settings, const renderer::SlabOptions& options,
                                   renderer::SlabCounters* counters) const {
    if (!m_pass) return renderer::renderImageAlignedSlabs(scene, plane, settings, options, counters);
    return m_pass->render(scene, plane, settings, options, counters);
}

std::string slabsText(const renderer::SlabOptions& options) {
    char text[128];
    const int ss = options.supersample;
    std::snprintf(text, sizeof text, "image-aligned slabs %g voxels thick%s%s", options.thickness,
                  options.postClassified ? ", post-classified" : "",
                  ss > 0 ? (", " + std::to_string(ss) + "x" + std::to_string(ss) + " samples a pixel").c_str() : "");
    return text;
}

std::optional<renderer::SlabOptions> slabsOfStillView(const ui::SlabView& slabs, const renderer::SplatSettings& s) {
    if (!slabs.enabled || s.compositing == renderer::Compositing::XRay || s.surfaceFlatten > 1.0) return std::nullopt;
    return renderer::SlabOptions{.thickness = slabs.thickness, .postClassified = slabs.postClassified};
}
