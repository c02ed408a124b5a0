// The split view in the viewport (its panes side by side, each labelled; the difference pane with its
// colour scale, RMSE and PSNR) and its controls in the Settings panel. The layout and the figures come
// from split_view.h; this file only draws them.
#include "split_viewport.h"

#include "ui/split_view.h"
#include "widgets.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

namespace ui {

namespace {

constexpr std::array kFilters{renderer::FilterMode::Reconstruction, renderer::FilterMode::LowPass,
                              renderer::FilterMode::Ewa, renderer::FilterMode::Adaptive};
constexpr std::array kCompositings{renderer::Compositing::SplatEverySample,
                                   renderer::Compositing::SheetBackToFront,
                                   renderer::Compositing::SheetFrontToBack, renderer::Compositing::XRay};

ImTextureID textureId(unsigned name) { return reinterpret_cast<ImTextureID>(static_cast<intptr_t>(name)); }

// A line of text over a dark band, so it reads over any image.
void labelAt(ImDrawList* draw, ImVec2 at, const char* text, ImU32 colour = IM_COL32(235, 235, 235, 255)) {
    const ImVec2 size = ImGui::CalcTextSize(text);
    draw->AddRectFilled(ImVec2(at.x - 3, at.y - 1), ImVec2(at.x + size.x + 3, at.y + size.y + 1),
                        IM_COL32(0, 0, 0, 170));
    draw->AddText(at, colour, text);
}

// The colour scale as a vertical bar at the pane's right edge, 0 at the bottom, scaleMax at the top.
void drawDifferenceScale(ImDrawList* draw, const ViewportDifference& d, ImVec2 min, ImVec2 max) {
    const float font = ImGui::GetFontSize(), barW = font * 0.8f,
                barH = std::min(max.y - min.y - 4 * font, 12 * font);
    if (barH < 2 * font) return;
    const float x1 = max.x - font * 0.6f, x0 = x1 - barW, y0 = max.y - font * 1.5f - barH, y1 = y0 + barH;
    constexpr int kSteps = 32;
    for (int i = 0; i < kSteps; ++i) { // top step is the scale's top
        const std::array<uint8_t, 3> rgb = differenceColour(1.0 - (double(i) + 0.5) / kSteps);
        draw->AddRectFilled(ImVec2(x0, y0 + barH * float(i) / kSteps),
                            ImVec2(x1, y0 + barH * float(i + 1) / kSteps),
                            IM_COL32(rgb[0], rgb[1], rgb[2], 255));
    }
    draw->AddRect(ImVec2(x0, y0), ImVec2(x1, y1), IM_COL32(200, 200, 200, 255));
    char top[32], mid[32];
    std::snprintf(top, sizeof top, "%.3g", d.scaleMax);
    std::snprintf(mid, sizeof mid, "%.3g", 0.5 * d.scaleMax);
    const auto leftOf = [&](const char* t, float y) {
        labelAt(draw, ImVec2(x0 - ImGui::CalcTextSize(t).x - 6, y - font * 0.5f), t);
    };
    leftOf(top, y0), leftOf(mid, 0.5f * (y0 + y1)), leftOf("0", y1);
}

} // namespace

bool drawSplitViewSection(EditorState& state, renderer::Compositing viewCompositing) {
    SplitView& split = state.split;
    bool changed = false;
    if (ImGui::Checkbox("Split view", &split.enabled)) {
        changed = true;
        if (split.enabled) // every pane starts in the view's compositing: only the filters differ
            for (SplitPane& pane : split.panes)
                pane.compositing = viewCompositing;
    }
    hint("Two or four panes at one camera (a drag in any moves all), each with its own filter and\n"
         "compositing; the rest of the settings above are shared. The heatmap is off meanwhile");
    if (!split.enabled) return changed;
    ImGui::TextUnformatted("Panes");
    ImGui::SameLine();
    changed |= ImGui::RadioButton("2", &split.imagePanes, 2);
    ImGui::SameLine();
    changed |= ImGui::RadioButton("4 (2 x 2)", &split.imagePanes, 4);
    static constexpr const char* kTitles[] = {"A (top left)", "B (top right)", "C (bottom left)",
                                              "D (bottom right)"};
    static constexpr const char* kTitlesInRow[] = {"A (left)", "B (right)"};
    for (int i = 0; i < split.shownImagePanes(); ++i) {
        ImGui::PushID(i);
        ImGui::TextUnformatted(split.imagePanes == 4 ? kTitles[i] : kTitlesInRow[i]);
        changed |=
            enumCombo("Filter##pane", split.panes[size_t(i)].filter, kFilters, &renderer::filterModeName);
        changed |= enumCombo("Compositing##pane", split.panes[size_t(i)].compositing, kCompositings,
                             &renderer::compositingName);
        ImGui::PopID();
    }
    constexpr std::array kDifferences{SplitDifference::Off, SplitDifference::AgainstB,
                                      SplitDifference::AgainstTruth};
    changed |= enumCombo(
        "Difference", split.difference, kDifferences, +[](SplitDifference d) -> const char* {
            return d == SplitDifference::Off        ? "none"
                   : d == SplitDifference::AgainstB ? "|A - B|"
                                                    : "|A - ground truth|";
        });
    hint("A pane more: each pixel's RMS difference of pane A's premultiplied RGBA against pane B's, or "
         "against\n"
         "the ground truth (the exact integral Measure compares with), on a colour scale, with the RMSE and "
         "PSNR\n"
         "of the whole pane (renderer::compareImages, the accuracy tests' metric). The truth takes seconds "
         "to\n"
         "minutes on a CPU: it starts once the camera rests, a quarter-size one first, and a move drops it");
    return changed;
}

void drawSplitPanes(const ViewportOverlay& overlay, float x, float y, float w, float h) {
    const ImVec2 origin{x, y}, extent{w, h};
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
    const int widthPx = int(std::lround(extent.x * scale.x)), heightPx = int(std::lround(extent.y * scale.y));
    const int imagePanes = int(std::count_if(overlay.panes.begin(), overlay.panes.end(),
                                             [](const ViewportPane& p) { return !p.isDifference; }));
    const std::vector<PaneRect> rects =
        splitPaneRects(widthPx, heightPx, imagePanes, imagePanes < int(overlay.panes.size()));
    const float font = ImGui::GetFontSize();
    for (size_t i = 0; i < rects.size() && i < overlay.panes.size(); ++i) {
        const ViewportPane& pane = overlay.panes[i];
        const ImVec2 min{origin.x + float(rects[i].x) / scale.x, origin.y + float(rects[i].y) / scale.y};
        const ImVec2 max{min.x + float(rects[i].width) / scale.x, min.y + float(rects[i].height) / scale.y};
        if (pane.texture != 0) draw->AddImage(textureId(pane.texture), min, max);
        if (rects[i].x > 0)
            draw->AddLine(ImVec2(min.x, min.y), ImVec2(min.x, max.y), IM_COL32(120, 120, 120, 255));
        if (rects[i].y > 0)
            draw->AddLine(ImVec2(min.x, min.y), ImVec2(max.x, min.y), IM_COL32(120, 120, 120, 255));
        if (pane.isDifference) // its own frame: beside a grid it does not fill its column
            draw->AddRect(min, max, IM_COL32(120, 120, 120, 255));
        labelAt(draw, ImVec2(min.x + font * 0.5f, min.y + font * 0.4f), pane.label.c_str());
        if (!pane.note.empty()) // below the figures, if any
            labelAt(draw, ImVec2(min.x + font * 0.5f, min.y + font * (pane.difference ? 3.2f : 1.8f)),
                    pane.note.c_str(), IM_COL32(255, 210, 120, 255));
        if (pane.difference) {
            char figures[96];
            std::snprintf(figures, sizeof figures, "RMSE %.5f   PSNR %.2f dB", pane.difference->rmse,
                          pane.difference->psnrDb);
            labelAt(draw, ImVec2(min.x + font * 0.5f, min.y + font * 1.8f), figures);
            drawDifferenceScale(draw, *pane.difference, min, max);
        }
    }
}

} // namespace ui
