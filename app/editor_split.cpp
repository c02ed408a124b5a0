// The split view's side of the editor loop (ui/split_view.h): each pane's settings in the view request, the
// panes and the difference pane shown, the pointer mapped into a pane, and Save image of the panes side by
// side. The render thread draws the panes (render_thread.cpp); the viewport lays them out (ui/).
#include "editor_loop.h"

#include <cstdio>

void EditorLoop::splitViewRequest(ViewRequest& request) const {
    const ui::SplitView& split = m_state.split;
    if (!split.enabled) return;
    // Each pane is the pane's size, not the viewport's: a frame computes only what is shown.
    const ui::PaneRect pane = ui::splitPaneRects(m_renderWidth, m_renderHeight, split.paneCount()).front();
    request.plane = renderer::makeImagePlane(m_state.camera, m_doc.scene.centre, m_doc.scene.radius,
                                             pane.width, pane.height, m_doc.scene.axes);
    const renderer::SplatSettings view = request.full;
    const auto withPane = [&](const ui::SplitPane& p, renderer::SplatSettings& full,
                              std::vector<renderer::SplatSettings>& coarse) {
        full = ui::paneSettings(view, p);
        full.heatmap = false;
        for (renderer::SplatSettings& level : coarse) {
            const double density = level.density; // a level's own extinction per unit length
            level = full;
            level.density = density;
        }
    };
    request.second = ViewRequest::SecondPane{.full = {}, .coarse = request.coarse};
    withPane(split.panes[1], request.second->full, request.second->coarse);
    withPane(split.panes[0], request.full, request.coarse);
    request.heatmap = false; // the heatmap belongs to the one image
    request.difference = split.difference;
}

void EditorLoop::showSplitPanes(RenderedView& view) {
    m_shownPanes = view.secondRgba.empty() ? 1 : view.difference ? 3 : 2;
    if (m_shownPanes > 1) m_secondImage.upload(view.width, view.height, view.secondRgba);
    if (view.difference)
        m_differenceImage.upload(view.difference->width, view.difference->height, view.difference->rgba);
    view.secondRgba = {};
    if (view.difference) view.difference->rgba = {};
}

std::vector<ui::ViewportPane> EditorLoop::splitPanes() const {
    if (!m_state.split.enabled || !m_shown || m_shownPanes < 2) return {};
    std::vector<ui::ViewportPane> panes{
        {m_image.id(), "A: " + ui::paneLabel(m_state.split.panes[0]), {}},
        {m_secondImage.id(), "B: " + ui::paneLabel(m_state.split.panes[1]), {}}};
    if (m_shownPanes == 3 && m_shown->difference)
        panes.push_back({m_differenceImage.id(), "|A - B|",
                         ui::ViewportDifference{m_shown->difference->rmse, m_shown->difference->psnrDb,
                                                m_shown->difference->scaleMax}});
    return panes;
}

std::optional<glm::dvec2> EditorLoop::pointerInPane() const {
    if (!m_viewport.hoverPx || !m_state.split.enabled || m_shownPanes < 2) return m_viewport.hoverPx;
    // The panes share one view: a pointer over any of them points at the same pixel of that view.
    for (const ui::PaneRect& pane : ui::splitPaneRects(m_renderWidth, m_renderHeight, m_shownPanes))
        if (m_viewport.hoverPx->x >= pane.x && m_viewport.hoverPx->x < pane.x + pane.width)
            return glm::dvec2(m_viewport.hoverPx->x - pane.x, m_viewport.hoverPx->y - pane.y);
    return std::nullopt;
}

std::future<EditorLoop::SplitImage> EditorLoop::startSaveSplitView(const ViewRequest& view) {
    return m_render->run([view](Renderers& r) {
        r.full->render(view.plane, view.second->full); // as the view: the first pane last
        const renderer::Image b = r.full->readback();
        r.full->render(view.plane, view.full);
        const renderer::Image a = r.full->readback();
        SplitImage split;
        if (view.difference) split.difference = ui::differencePane(a, b);
        const int w = a.width, h = a.height, count = view.difference ? 3 : 2;
        split.panes = renderer::Image(w * count, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 4; ++c) {
                    split.panes.pixel(x, y)[c] = a.pixel(x, y)[c];
                    split.panes.pixel(w + x, y)[c] = b.pixel(x, y)[c];
                    if (split.difference) // the colour scale, opaque: written as it is over any background
                        split.panes.pixel(2 * w + x, y)[c] =
                            float(
                                split.difference->rgba[(size_t(y) * size_t(w) + size_t(x)) * 4 + size_t(c)]) /
                            255.0f;
                }
        if (split.difference) split.difference->rgba = {};
        return split;
    });
}

std::string EditorLoop::splitSavedText(const SplitImage& split) const {
    std::string text = " (split: A " + ui::paneLabel(m_state.split.panes[0]) + " | B " +
                       ui::paneLabel(m_state.split.panes[1]);
    if (split.difference) {
        char figures[96];
        std::snprintf(figures, sizeof figures, " | |A - B| RMSE %.9g PSNR %.4f dB", split.difference->rmse,
                      split.difference->psnrDb);
        text += figures;
    }
    return text + ")";
}
