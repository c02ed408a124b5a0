// The split view's side of the editor loop (ui/split_view.h): each pane's settings in the view request, the
// panes and the difference pane shown (|A - B| from the render thread, |A - ground truth| against
// split_truth.h's truth of the view), the pointer mapped into a pane, and Save image of the panes in their
// layout. The render thread draws the panes (render_thread.cpp); the viewport lays them out (ui/).
#include "editor_loop.h"

#include "renderer/oracle/ground_truth.h"

#include <cstdio>

namespace {

constexpr const char* kPaneNames[] = {"A", "B", "C", "D"};

} // namespace

void EditorLoop::splitViewRequest(ViewRequest& request) const {
    const ui::SplitView& split = m_state.split;
    if (!split.enabled) return;
    // Each pane is the pane's size, not the viewport's: a frame computes only what is shown.
    const ui::PaneRect pane = ui::splitLayout(m_renderWidth, m_renderHeight, split.shownImagePanes(),
                                              split.difference != ui::SplitDifference::Off)
                                  .panes.front();
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
    request.others.assign(size_t(split.shownImagePanes() - 1),
                          ViewRequest::OtherPane{.full = {}, .coarse = request.coarse});
    for (size_t i = 0; i < request.others.size(); ++i)
        withPane(split.panes[i + 1], request.others[i].full, request.others[i].coarse);
    withPane(split.panes[0], request.full, request.coarse);
    request.heatmap = false; // the heatmap belongs to the one image
    request.difference = split.difference == ui::SplitDifference::AgainstB;
    request.keepFirstPane = split.difference == ui::SplitDifference::AgainstTruth;
    if (request.keepFirstPane)
        request.truthKey = SplitTruth::viewKey(request.plane, request.full, m_sceneVersion);
}

void EditorLoop::showSplitPanes(RenderedView& view) {
    m_shownPanes = 1 + int(view.otherRgba.size());
    for (size_t i = 0; i < view.otherRgba.size() && i < m_otherImages.size(); ++i)
        m_otherImages[i].upload(view.width, view.height, view.otherRgba[i]);
    if (view.difference)
        m_differenceImage.upload(view.difference->width, view.difference->height, view.difference->rgba);
    view.otherRgba = {};
    if (view.difference) view.difference->rgba = {};
}

void EditorLoop::stepSplitTruth() {
    const ui::SplitView& split = m_state.split;
    if (!split.enabled || split.difference != ui::SplitDifference::AgainstTruth || !m_hasScene ||
        m_renderWidth <= 0) {
        if (m_truth) m_truth->clear(); // cancelled, not joined: its worker ends on its own
        m_truthDifference.reset();
        return;
    }
    if (!m_truth) // scripted runs start at once and wait for it; the editor once the view rests, below the UI
        m_truth = std::make_unique<SplitTruth>(
            renderer::defaultGroundTruthCacheDir(),
            m_scripted ? SplitTruth::Clock::duration{} : std::chrono::milliseconds(300), !m_scripted);
    const ViewRequest request = viewRequest();
    m_truthUnavailable.clear();
    if (!renderer::hasGroundTruth(request.full)) { // as Measure: surface splats have none
        m_truth->clear();
        m_truthUnavailable = "no ground truth with surface splats";
        return;
    }
    // Not while the full scene is being re-classified: the truth would be of the window left behind.
    if (!m_classifyJob && !m_fullWindowStale)
        m_truth->want(request.truthKey, request.plane, request.full,
                      [this] { return copyForRender(m_doc.scene); });
    if (m_scripted) m_truth->waitUntilDone();
    // The difference of the A image shown against the truth of its own view, once per (image, truth); of
    // full frames only (a preview level's image is not what the truth is compared with).
    const std::optional<SplitTruth::Truth> truth = m_truth->latest();
    if (!truth || !m_shown || !m_shown->firstPane || m_shown->level != 0 || m_shown->truthKey != truth->key)
        return;
    const auto of = std::tuple{m_shown->request, truth->computedWidth, truth->computedHeight};
    if (m_truthDifference && m_truthDifference->of == of) return;
    guarded([&] {
        ui::DifferencePane d = ui::differencePane(*m_shown->firstPane, *truth->image);
        m_differenceImage.upload(d.width, d.height, d.rgba);
        d.rgba = {};
        m_truthDifference = TruthDifference{.of = of,
                                            .key = truth->key,
                                            .truth = truth->image,
                                            .coarse = truth->coarse,
                                            .pane = std::move(d),
                                            .seconds = truth->seconds,
                                            .cached = truth->cached};
    });
}

std::string EditorLoop::truthLabel() const {
    char text[96];
    if (!m_truthDifference) return "|A - truth|";
    const auto& t = *m_truthDifference;
    // The time is from the view's start (the camera at rest) to this truth: what the next one will cost.
    char took[32] = "cached";
    if (!t.cached) std::snprintf(took, sizeof took, "%.1f s", t.seconds);
    std::snprintf(text, sizeof text, "|A - truth|, %struth %dx%d (%s)", t.coarse ? "coarse " : "",
                  std::get<1>(t.of), std::get<2>(t.of), took);
    return text;
}

std::vector<ui::ViewportPane> EditorLoop::splitPanes() const {
    const ui::SplitView& split = m_state.split;
    if (!split.enabled || !m_shown || m_shownPanes < 2) return {};
    std::vector<ui::ViewportPane> panes{{m_image.id(), "A: " + ui::paneLabel(split.panes[0]), {}, {}, false}};
    for (int i = 1; i < m_shownPanes; ++i)
        panes.push_back({m_otherImages[size_t(i - 1)].id(),
                         std::string(kPaneNames[i]) + ": " + ui::paneLabel(split.panes[size_t(i)]),
                         {},
                         {},
                         false});
    if (split.difference == ui::SplitDifference::AgainstB && m_shown->difference)
        panes.push_back({m_differenceImage.id(),
                         "|A - B|",
                         ui::ViewportDifference{m_shown->difference->rmse, m_shown->difference->psnrDb,
                                                m_shown->difference->scaleMax},
                         {},
                         true});
    if (split.difference == ui::SplitDifference::AgainstTruth) {
        // Only a difference of the A image shown against the truth of that same view; else why not.
        const bool current = m_truthDifference && m_shown->truthKey == m_truthDifference->key;
        ui::ViewportPane pane{0, current ? truthLabel() : "|A - truth|", {}, {}, true};
        if (current) {
            pane.texture = m_differenceImage.id();
            const ui::DifferencePane& d = m_truthDifference->pane;
            pane.difference = ui::ViewportDifference{d.rmse, d.psnrDb, d.scaleMax};
            if (m_truthDifference->coarse && m_truth && m_truth->computing())
                pane.note = "upsampled; computing " + std::to_string(d.width) + "x" +
                            std::to_string(d.height) + "...";
        } else if (!m_truthUnavailable.empty()) {
            pane.note = m_truthUnavailable;
        } else if (const auto error = m_truth ? m_truth->error() : std::nullopt) {
            pane.note = "ground truth failed: " + *error;
        } else {
            pane.note = m_truth && !m_truth->coarseComputing() ? "ground truth: computing..."
                                                               : "ground truth: computing (coarse)...";
        }
        panes.push_back(std::move(pane));
    }
    return panes;
}

std::optional<glm::dvec2> EditorLoop::pointerInPane() const {
    const ui::SplitView& split = m_state.split;
    if (!m_viewport.hoverPx || !split.enabled || m_shownPanes < 2) return m_viewport.hoverPx;
    // The panes share one view: a pointer over any of them points at the same pixel of that view.
    for (const ui::PaneRect& pane : ui::splitPaneRects(m_renderWidth, m_renderHeight, m_shownPanes,
                                                       split.difference != ui::SplitDifference::Off))
        if (m_viewport.hoverPx->x >= pane.x && m_viewport.hoverPx->x < pane.x + pane.width &&
            m_viewport.hoverPx->y >= pane.y && m_viewport.hoverPx->y < pane.y + pane.height)
            return glm::dvec2(m_viewport.hoverPx->x - pane.x, m_viewport.hoverPx->y - pane.y);
    return std::nullopt;
}

std::future<EditorLoop::SplitImage> EditorLoop::startSaveSplitView(const ViewRequest& view) {
    // |A - truth| against the truth of this very view, if there is one yet (else the pane stays empty and
    // the message says why).
    std::shared_ptr<const renderer::Image> truth;
    std::string truthOf;
    if (view.keepFirstPane && m_truthDifference && m_truthDifference->key == view.truthKey) {
        truth = m_truthDifference->truth;
        char text[96];
        std::snprintf(text, sizeof text, " against the truth at %dx%d%s", std::get<1>(m_truthDifference->of),
                      std::get<2>(m_truthDifference->of),
                      m_truthDifference->coarse ? " (coarse, upsampled)" : "");
        truthOf = text;
    }
    const bool differenceOn = m_state.split.difference != ui::SplitDifference::Off;
    return m_render->run([view, truth, truthOf, differenceOn](Renderers& r) {
        std::vector<renderer::Image> panes(view.others.size() + 1);
        for (size_t i = view.others.size(); i-- > 0;) { // as the view: the first pane last
            r.full->render(view.plane, view.others[i].full);
            panes[i + 1] = r.full->readback();
        }
        r.full->render(view.plane, view.full);
        panes[0] = r.full->readback();
        SplitImage split;
        if (view.difference) split.difference = ui::differencePane(panes[0], panes[1]);
        if (truth)
            split.difference = ui::differencePane(panes[0], *truth), split.against = "truth",
            split.truthOf = truthOf;
        const int w = panes[0].width, h = panes[0].height;
        // The layout the viewport shows, at the pane's size (splitLayout over the panes' whole extent).
        const int columns = 2 + (differenceOn ? 1 : 0), rows = panes.size() == 4 ? 2 : 1;
        const ui::SplitLayout layout =
            ui::splitLayout(w * columns, h * rows, int(panes.size()), differenceOn);
        split.panes = renderer::Image(w * columns, h * rows); // transparent: the background where no pane is
        const auto place = [&](const ui::PaneRect& at, auto pixel) {
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    for (int c = 0; c < 4; ++c)
                        split.panes.pixel(at.x + x, at.y + y)[c] = pixel(x, y, c);
        };
        for (size_t i = 0; i < panes.size(); ++i)
            place(layout.panes[i], [&](int x, int y, int c) { return panes[i].pixel(x, y)[c]; });
        if (split.difference) // the colour scale, opaque: written as it is over any background
            place(*layout.difference, [&](int x, int y, int c) {
                return float(split.difference->rgba[(size_t(y) * size_t(w) + size_t(x)) * 4 + size_t(c)]) /
                       255.0f;
            });
        if (split.difference) split.difference->rgba = {};
        return split;
    });
}

std::string EditorLoop::splitSavedText(const SplitImage& split) const {
    std::string text = " (split:";
    for (int i = 0; i < m_state.split.shownImagePanes(); ++i)
        text += std::string(i ? " |" : "") + " " + kPaneNames[i] + " " +
                ui::paneLabel(m_state.split.panes[size_t(i)]);
    char figures[160];
    if (split.difference) {
        std::snprintf(figures, sizeof figures, " | |A - %s| RMSE %.9g PSNR %.4f dB", split.against.c_str(),
                      split.difference->rmse, split.difference->psnrDb);
        text += figures + split.truthOf;
    } else if (m_state.split.difference == ui::SplitDifference::AgainstTruth) {
        text += " | |A - truth| left empty: " + (m_truthUnavailable.empty()
                                                     ? std::string("the ground truth is still computing")
                                                     : m_truthUnavailable);
    }
    return text + ")";
}
