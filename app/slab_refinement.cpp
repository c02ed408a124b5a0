// The editor's image-aligned slab frames (see slab_refinement.h).
#include "slab_refinement.h"

#include "renderer/errors.h"

#include <algorithm>
#include <cmath>

void SlabRefinement::setInputs(std::shared_ptr<const renderer::SplatScene> full,
                               std::shared_ptr<const renderer::SplatScene> gradients,
                               std::optional<renderer::TfTables> tables) {
    if (full != m_full || gradients != m_gradients) m_copy.reset();
    m_full = std::move(full), m_gradients = std::move(gradients), m_tables = std::move(tables);
    m_tablesStale = true;
}

const renderer::SplatScene& SlabRefinement::scene() {
    if (!m_copy) {
        m_copy = std::make_unique<renderer::SplatScene>(*m_full);   // the lists' entries stay shared
        if (m_gradients && m_gradients->gradients.size() == m_copy->classes.size())
            m_copy->gradients = m_gradients->gradients;
        m_tablesStale = true;
    }
    if (m_tablesStale && m_tables) {
        m_copy->lut = m_tables->lut;
        // Gradient opacity and a 2D TF read each voxel's gradient: only with them.
        const bool withGradients = m_copy->gradients.size() == m_copy->classes.size();
        m_copy->gradientFactors = withGradients ? m_tables->gradientFactors : renderer::GradientFactors{};
        m_copy->tf2d = withGradients ? m_tables->tf2d : renderer::Tf2dTable{};
    }
    m_tablesStale = false;
    return *m_copy;
}

renderer::Image SlabRefinement::render(const renderer::ImagePlane& plane, const renderer::SplatSettings& settings,
                                       const renderer::SlabOptions& options, std::function<bool()> interrupted) {
    if (!m_full) throw renderer::RenderError("image-aligned slabs: no volume shown");
    if (!m_pass) m_pass = std::make_unique<renderer::ImageSlabsGl>();
    struct InterruptScope {   // the interrupt reads the caller's locals: it goes with the frame
        renderer::ImageSlabsGl& pass;
        ~InterruptScope() { pass.setInterrupt({}); }
    } scope{*m_pass};
    m_pass->setInterrupt(std::move(interrupted));
    return m_pass->render(scene(), plane, settings, options);
}

std::vector<uint8_t> displayPixels(const renderer::Image& image, const float background[3]) {
    std::vector<uint8_t> rgba(size_t(image.width) * size_t(image.height) * 4);
    for (size_t i = 0; i < rgba.size() / 4; ++i) {
        const float* p = &image.rgba[4 * i];
        for (int c = 0; c < 3; ++c) {
            const float v = p[c] + (1.0f - p[3]) * background[c];
            rgba[4 * i + size_t(c)] = uint8_t(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
        }
        rgba[4 * i + 3] = 255;
    }
    return rgba;
}
