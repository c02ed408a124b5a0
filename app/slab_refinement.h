// The editor's image-aligned slab frames (renderer/gl/image_slabs_gl.h) on the render thread: a still view
// of the full scene drawn again with slabs after its sheets frame (ViewRequest::slabs). The slab pass reads
// the scene's classes, LUT and gradients from one SplatScene, where the render thread holds the three apart
// (a TF edit sends only the tables); this keeps the copy it renders from, made again only when the scene
// or its gradients change, and only once a slab frame is asked for.
#pragma once
#include "renderer/gl/image_slabs_gl.h"
#include "renderer/model/splat_scene.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

class SlabRefinement {
public:
    // What the render thread shows: the full scene, its gradients (a scene holding only them; none before
    // they are computed) and the tables of the TF shown (none: the scene's own).
    void setInputs(std::shared_ptr<const renderer::SplatScene> full, std::shared_ptr<const renderer::SplatScene> gradients,
                   std::optional<renderer::TfTables> tables);
    // A slab frame of the inputs; needs the render thread's GL context. Throws RenderError (a setting the
    // slabs do not take), Cancelled (`interrupted` said so) and GlError.
    renderer::Image render(const renderer::ImagePlane& plane, const renderer::SplatSettings& settings,
                           const renderer::SlabOptions& options, std::function<bool()> interrupted = {});

private:
    const renderer::SplatScene& scene();   // the copy, brought up to date with the inputs

    std::unique_ptr<renderer::ImageSlabsGl> m_pass;   // made at the first slab frame
    std::shared_ptr<const renderer::SplatScene> m_full, m_gradients;
    std::optional<renderer::TfTables> m_tables;
    std::unique_ptr<renderer::SplatScene> m_copy;     // none: to make from the inputs
    bool m_tablesStale = true;
};

// A float image (row 0 at the top, premultiplied) over `background`, 8 bits a channel: as the display
// shader shows a renderer's image.
std::vector<uint8_t> displayPixels(const renderer::Image& image, const float background[3]);
