// The Transfer function panel: presets, the curve editor over the histogram, the selected point's
// fields, and TF files. The edit rules are tf_editor.h's; this file only maps ImGui input onto them.
#include "ui/file_browser.h"
#include "ui/panels.h"
#include "ui/tf_editor.h"
#include "widgets.h"

#include "renderer/errors.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

namespace ui {

namespace {

constexpr float kPointRadiusPx = 5.0f;
constexpr float kPickRadiusPx = 8.0f;   // a little more than the drawn dot: easy to grab
constexpr float kStopHalfWidthPx = 5.0f; // a colour stop's marker, each side of its value

ImU32 colourOf(const glm::dvec3& c, float alpha = 1.0f) {
    return ImGui::GetColorU32(ImVec4(float(c.r), float(c.g), float(c.b), alpha));
}

// The histogram's bins inside the window, log counts, behind the curve.
void drawHistogram(ImDrawList* draw, const Rect& canvas, const renderer::Histogram& h, renderer::ValueRange window) {
    const size_t bins = h.counts.size();
    if (bins == 0 || !(window.hi > window.lo)) return;
    double peak = 0.0;
    for (uint64_t c : h.counts) peak = std::max(peak, std::log1p(double(c)));
    if (!(peak > 0.0)) return;
    const double width = (double(h.range.hi) - double(h.range.lo)) / double(bins);
    for (size_t i = 0; i < bins; ++i) {
        if (h.counts[i] == 0) continue;
        const double lo = h.range.lo + width * double(i), hi = lo + width;
        const double t0 = (lo - window.lo) / (double(window.hi) - window.lo);
        const double t1 = (hi - window.lo) / (double(window.hi) - window.lo);
        if (t1 <= 0.0 || t0 >= 1.0) continue;
        const float x0 = canvas.x + float(std::max(t0, 0.0)) * canvas.w;
        const float x1 = std::max(canvas.x + float(std::min(t1, 1.0)) * canvas.w, x0 + 1.0f);
        const float top = canvas.bottom() - float(std::log1p(double(h.counts[i])) / peak) * canvas.h;
        draw->AddRectFilled(ImVec2(x0, top), ImVec2(x1, canvas.bottom()), IM_COL32(120, 125, 140, 70));
    }
}

// The curve: the TF's colour filled up to its opacity, the polyline, and the opacity points (the selected
// one larger, outlined in the accent colour). The canvas spans `window`; points outside it are not drawn.
void drawCurve(ImDrawList* draw, const Rect& canvas, const renderer::TransferFunction& tf,
               renderer::ValueRange window, int selected, OpacityAxis axis) {
    std::vector<ImVec2> line;
    for (float x = 0.0f; x < canvas.w; x += 2.0f) {
        const double fraction = (double(x) + 1.0) / canvas.w;
        const glm::dvec4 c = renderer::evaluate(tf, toDataUnits(fraction, window));
        const float top = tfToCanvas(canvas, fraction, c.a, axis).y;
        draw->AddRectFilled(ImVec2(canvas.x + x, top), ImVec2(canvas.x + std::min(x + 2.0f, canvas.w), canvas.bottom()),
                            colourOf(glm::dvec3(c), 0.55f));
        line.emplace_back(canvas.x + x + 1.0f, top);
    }
    const auto& pts = tf.opacities;
    const auto at = [&](size_t i) { return tfToCanvas(canvas, windowFraction(pts[i].value, window), pts[i].opacity, axis); };
    draw->PushClipRect(ImVec2(canvas.x, canvas.y), ImVec2(canvas.right(), canvas.bottom()), true);
    // Linear: straight segments between the points; log: the segments (linear in opacity) bend, so the
    // line follows the sampled curve.
    if (axis == OpacityAxis::Log)
        draw->AddPolyline(line.data(), int(line.size()), IM_COL32(235, 235, 240, 255), 0, 1.5f);
    for (size_t i = 0; i + 1 < pts.size() && axis == OpacityAxis::Linear; ++i) {
        const CanvasPoint a = at(i), b = at(i + 1);
        draw->AddLine(ImVec2(a.x, a.y), ImVec2(b.x, b.y), IM_COL32(235, 235, 240, 255), 1.5f);
    }
    // The axis: what it measures, and on a log axis a line and a label a decade.
    const ImU32 label = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    if (axis == OpacityAxis::Log)
        for (int d = 1; d < int(kLogOpacityDecades); ++d) {
            const double level = std::pow(10.0, -d);
            const float y = tfToCanvas(canvas, 0.0, level, axis).y;
            draw->AddLine(ImVec2(canvas.x, y), ImVec2(canvas.right(), y), IM_COL32(255, 255, 255, 30));
            char text[16];
            std::snprintf(text, sizeof text, "%g", level);
            draw->AddText(ImVec2(canvas.x + 3.0f, y - ImGui::GetFontSize()), label, text);
        }
    draw->AddText(ImVec2(canvas.x + 3.0f, canvas.y + 2.0f), label,
                  axis == OpacityAxis::Log ? "extinction / voxel length (log)" : "extinction / voxel length");
    for (size_t i = 0; i < pts.size(); ++i) {
        const CanvasPoint p = at(i);
        const bool chosen = int(i) == selected;
        const float r = chosen ? kPointRadiusPx + 2.0f : kPointRadiusPx;
        draw->AddCircleFilled(ImVec2(p.x, p.y), r, IM_COL32(250, 250, 250, 255));
        draw->AddCircle(ImVec2(p.x, p.y), r, chosen ? IM_COL32(255, 200, 80, 255) : IM_COL32(60, 60, 70, 255), 0,
                        chosen ? 2.0f : 1.0f);
    }
    draw->PopClipRect();
}

// The colour bar (the TF's colour at each value, whatever its opacity) and its stops: a marker per colour
// stop, filled with its colour, spanning the bar's height below a strip of the gradient.
void drawColourBar(ImDrawList* draw, const Rect& bar, float gradientH, const renderer::TransferFunction& tf,
                   renderer::ValueRange window, int selected) {
    draw->AddRectFilled(ImVec2(bar.x, bar.y), ImVec2(bar.right(), bar.bottom()), ImGui::GetColorU32(ImGuiCol_FrameBg));
    for (float x = 0.0f; x < bar.w; x += 2.0f)
        draw->AddRectFilled(ImVec2(bar.x + x, bar.y), ImVec2(bar.x + std::min(x + 2.0f, bar.w), bar.y + gradientH),
                            colourOf(glm::dvec3(renderer::evaluate(tf, toDataUnits((double(x) + 1.0) / bar.w, window)))));
    draw->PushClipRect(ImVec2(bar.x - kStopHalfWidthPx, bar.y), ImVec2(bar.right() + kStopHalfWidthPx, bar.bottom()), true);
    for (size_t i = 0; i < tf.colours.size(); ++i) {
        const float x = tfToCanvas(bar, windowFraction(tf.colours[i].value, window), 0.0).x;
        const bool chosen = int(i) == selected;
        const float top = bar.y + gradientH, w = chosen ? kStopHalfWidthPx + 1.5f : kStopHalfWidthPx;
        // A house shape: its point up into the gradient, its body the stop's colour.
        const ImVec2 shape[5] = {ImVec2(x, top - 4.0f), ImVec2(x + w, top + 2.0f), ImVec2(x + w, bar.bottom() - 1.0f),
                                 ImVec2(x - w, bar.bottom() - 1.0f), ImVec2(x - w, top + 2.0f)};
        draw->AddConvexPolyFilled(shape, 5, colourOf(tf.colours[i].colour));
        draw->AddPolyline(shape, 5, chosen ? IM_COL32(255, 200, 80, 255) : IM_COL32(240, 240, 240, 255),
                          ImDrawFlags_Closed, chosen ? 2.0f : 1.0f);
    }
    draw->PopClipRect();
}

// The Gallery: each preset's thumbnail (a placeholder until the editor has drawn it) with its name under
// it, as many to a row as fit. Returns the name clicked, if any.
std::optional<std::string> drawGallery(const std::vector<GalleryThumbnail>& gallery) {
    if (gallery.empty()) {
        ImGui::TextDisabled("Open a volume to see each preset drawn on it");
        return std::nullopt;
    }
    const float side = 96.0f; // the thumbnails' own size (kThumbnailPx): drawn 1:1
    const float spacing = ImGui::GetStyle().ItemSpacing.x;
    const float right = ImGui::GetCursorScreenPos().x + ImGui::GetContentRegionAvail().x;
    std::optional<std::string> picked;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (size_t i = 0; i < gallery.size(); ++i) {
        const GalleryThumbnail& t = gallery[i];
        ImGui::PushID(t.name.c_str());
        ImGui::BeginGroup();
        const ImVec2 at = ImGui::GetCursorScreenPos();
        if (ImGui::InvisibleButton("thumbnail", ImVec2(side, side))) picked = t.name;
        const bool hovered = ImGui::IsItemHovered();
        const ImVec2 end(at.x + side, at.y + side);
        if (t.texture)
            draw->AddImage(ImTextureID(intptr_t(t.texture)), at, end);
        else {
            draw->AddRectFilled(at, end, ImGui::GetColorU32(ImGuiCol_FrameBg));
            draw->AddText(ImVec2(at.x + 6.0f, at.y + 6.0f), ImGui::GetColorU32(ImGuiCol_TextDisabled),
                          "drawing...");
        }
        draw->AddRect(at, end, hovered ? IM_COL32(255, 200, 80, 255) : IM_COL32(90, 90, 100, 255), 0.0f, 0,
                      hovered ? 2.0f : 1.0f);
        // The name, cut to the thumbnail's width (the tooltip has it whole).
        std::string label = t.name;
        while (label.size() > 1 && ImGui::CalcTextSize(label.c_str()).x > side)
            label.pop_back();
        ImGui::TextUnformatted(label.c_str());
        ImGui::EndGroup();
        if (hovered) ImGui::SetTooltip("%s: click to apply", t.name.c_str());
        ImGui::PopID();
        if (i + 1 < gallery.size() && ImGui::GetItemRectMax().x + spacing + side <= right) ImGui::SameLine();
    }
    return picked;
}

} // namespace

bool drawTransferFunctionPanel(EditorState& state, const TransferFunctionView& view) {
    renderer::TransferFunction& tf = state.tf;
    // With no window yet (no volume shown), the canvas spans 0..1: a TF in window fractions shows as it is.
    const renderer::ValueRange window = view.window.hi > view.window.lo ? view.window : renderer::ValueRange{0.0f, 1.0f};
    bool changed = false;
    auto replace = [&](renderer::TransferFunction loaded) {
        tf = std::move(loaded);
        state.tfSelected = state.tfColourSelected = -1;
        state.tfEdited = false;
        changed = true;
    };
    // A TF in window fractions (a built-in preset, a version-1 file) is fixed in data units over the window
    // it is shown with: from now on the window no longer moves it. The LUT is the same.
    if (tf.windowFractions && view.window.hi > view.window.lo && view.windowSettled) {
        tf = renderer::inDataUnits(tf, window);
        if (state.tfGestureStart) *state.tfGestureStart = renderer::inDataUnits(*state.tfGestureStart, window);
        changed = true;
    }
    if (state.tfSelected >= int(tf.opacities.size())) state.tfSelected = -1;
    if (state.tfColourSelected >= int(tf.colours.size())) state.tfColourSelected = -1;
    if (!state.tfGestureStart) state.tfGestureStart = tf;

    // 1. Preset.
    sectionTitle("Transfer function");
    const std::string shown = tf.name + (state.tfEdited ? " (edited)" : "");
    if (ImGui::BeginCombo("Preset", shown.c_str())) {
        for (const std::string& name : renderer::builtinPresetNames())
            if (ImGui::Selectable(name.c_str(), name == tf.name && !state.tfEdited)) try {
                    replace(renderer::inDataUnits(renderer::builtinPreset(name), window));
                } catch (const renderer::LoadError& e) {   // a bundled file that is not a TF
                    state.errorMessage = e.what();
                }
        ImGui::EndCombo();
    }
    hint("Transfer functions: value -> colour and extinction; the built-in ones, then each NAME.json in\n"
         "assets/presets. Picking one replaces the curve below");

    // 2. The opacity curve. One button over the canvas takes left presses (pick or add, then drag) and
    //    right clicks (remove).
    const auto [canvas, mouse, moved] = canvasInput("##tf_canvas", ImGui::GetFontSize() * 11.0f);
    const OpacityAxis axis = state.tfLogOpacity ? OpacityAxis::Log : OpacityAxis::Linear;
    if (ImGui::IsItemActivated() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        int picked = pickOpacityPoint(tf, window, canvas, mouse, kPickRadiusPx, axis);
        if (picked < 0) {   // empty space: a new point under the mouse
            double fraction = 0, opacity = 0;
            canvasToTf(canvas, mouse, fraction, opacity, axis);
            picked = insertOpacityPoint(tf, toDataUnits(fraction, window), opacity);
            state.tfEdited = changed = true;
        }
        const auto& p = tf.opacities[size_t(picked)];
        const CanvasPoint at = tfToCanvas(canvas, windowFraction(p.value, window), p.opacity, axis);
        state.tfSelected = picked, state.tfColourSelected = -1;
        state.tfGrabDx = at.x - mouse.x, state.tfGrabDy = at.y - mouse.y;
    } else if (ImGui::IsItemActive() && ImGui::IsMouseDown(ImGuiMouseButton_Left) && state.tfSelected >= 0 && moved) {
        double fraction = 0, opacity = 0;
        canvasToTf(canvas, {mouse.x + state.tfGrabDx, mouse.y + state.tfGrabDy}, fraction, opacity, axis);
        const renderer::OpacityPoint before = tf.opacities[size_t(state.tfSelected)];
        moveOpacityPoint(tf, state.tfSelected, toDataUnits(fraction, window), opacity);
        if (tf.opacities[size_t(state.tfSelected)] != before) state.tfEdited = changed = true;
    }
    if (ImGui::IsItemClicked(ImGuiMouseButton_Right) &&
        removeOpacityPoint(tf, pickOpacityPoint(tf, window, canvas, mouse, kPickRadiusPx, axis))) {
        state.tfSelected = -1;
        state.tfEdited = changed = true;
    }
    const bool canvasHovered = ImGui::IsItemHovered();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(ImVec2(canvas.x, canvas.y), ImVec2(canvas.right(), canvas.bottom()),
                        ImGui::GetColorU32(ImGuiCol_FrameBg));
    if (view.histogram) drawHistogram(draw, canvas, *view.histogram, window);
    drawCurve(draw, canvas, tf, window, state.tfSelected, axis);
    // The value of the voxel the mouse points at in the viewport, where it falls on this axis; none
    // outside the window (fromDataUnits would clamp it to an end).
    if (state.probe && state.probe->value >= window.lo && state.probe->value <= window.hi) {
        const float x = tfToCanvas(canvas, fromDataUnits(state.probe->value, window), 0.0).x;
        draw->AddLine(ImVec2(x, canvas.y), ImVec2(x, canvas.bottom()), kProbeMarkerColour, 2.0f);
    }
    if (canvasHovered) {
        const int over = pickOpacityPoint(tf, window, canvas, mouse, kPickRadiusPx, axis);
        double fraction = 0, opacity = 0;
        canvasToTf(canvas, mouse, fraction, opacity, axis);
        double value = toDataUnits(fraction, window);
        if (over >= 0) value = tf.opacities[size_t(over)].value, opacity = tf.opacities[size_t(over)].opacity;
        else opacity = renderer::evaluate(tf, value).a;
        ImGui::SetTooltip("%s %.5g (data units), extinction %.4g per voxel length at density 1\n%s",
                          over >= 0 ? "opacity point at" : "value", value, opacity,
                          over >= 0 ? "drag to move, right-click to remove" : "click to add an opacity point here");
    }

    // 3. The colour bar with its stops, under the curve and over the same values: the same gestures, across
    //    only. A colour stop's drag never touches opacity, nor an opacity point's colour.
    ImGui::Dummy(ImVec2(canvas.w, 2.0f));
    const float gradientH = ImGui::GetFontSize() * 0.6f;
    const Rect bar = canvasInput("##tf_colour_bar", gradientH + ImGui::GetFontSize() * 0.9f, canvas.w).rect;
    if (ImGui::IsItemActivated() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        int picked = pickColourStop(tf, window, bar, mouse, kStopHalfWidthPx + 2.0f);
        if (picked < 0) {
            picked = insertColourStop(tf, toDataUnits(std::clamp(double(mouse.x - bar.x) / bar.w, 0.0, 1.0), window));
            state.tfEdited = changed = true;
        }
        state.tfColourSelected = picked, state.tfSelected = -1;
        state.tfGrabDx = tfToCanvas(bar, windowFraction(tf.colours[size_t(picked)].value, window), 0.0).x - mouse.x;
    } else if (ImGui::IsItemActive() && ImGui::IsMouseDown(ImGuiMouseButton_Left) && state.tfColourSelected >= 0 &&
               moved) {
        const double before = tf.colours[size_t(state.tfColourSelected)].value;
        const double fraction = std::clamp(double(mouse.x + state.tfGrabDx - bar.x) / bar.w, 0.0, 1.0);
        moveColourStop(tf, state.tfColourSelected, toDataUnits(fraction, window));
        if (tf.colours[size_t(state.tfColourSelected)].value != before) state.tfEdited = changed = true;
    }
    if (ImGui::IsItemClicked(ImGuiMouseButton_Right) &&
        removeColourStop(tf, pickColourStop(tf, window, bar, mouse, kStopHalfWidthPx + 2.0f))) {
        state.tfColourSelected = -1;
        state.tfEdited = changed = true;
    }
    if (ImGui::IsItemHovered()) {
        const int over = pickColourStop(tf, window, bar, mouse, kStopHalfWidthPx + 2.0f);
        const double value = over >= 0 ? tf.colours[size_t(over)].value : toDataUnits((mouse.x - bar.x) / bar.w, window);
        ImGui::SetTooltip("%s %.5g (data units)\n%s", over >= 0 ? "colour stop at" : "value", value,
                          over >= 0 ? "drag to move, right-click to remove" : "click to add a colour stop here");
    }
    drawColourBar(draw, bar, gradientH, tf, window, state.tfColourSelected);
    ImGui::TextDisabled("%.5g", double(window.lo));
    // Between the window's ends, as tall as their text (no frame padding), so nothing below moves.
    ImGui::SameLine(0.3f * canvas.w);
    ImGui::PushStyleVar(ImGuiStyleVar_FramePadding, ImVec2(2.0f, 0.0f));
    ImGui::Checkbox("log axis", &state.tfLogOpacity);
    ImGui::PopStyleVar();
    hint("The curve's axis in decades (1 down to 0.001): room for the faint values air and skin need.\n"
         "A point dragged to the baseline is exactly 0, to the top exactly 1");
    const std::string hiText = [&] {
        char text[32];
        std::snprintf(text, sizeof text, "%.5g", double(window.hi));
        return std::string(text);
    }();
    ImGui::SameLine(std::max(canvas.w - ImGui::CalcTextSize(hiText.c_str()).x, 0.0f) + ImGui::GetStyle().WindowPadding.x);
    ImGui::TextDisabled("%s", hiText.c_str());

    // 4. The selected point's fields: value in data units, and its opacity or colour; remove.
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 6.0f); // room for "Extinction"
    const float valueSpeed = float((double(window.hi) - double(window.lo)) / 1000.0);
    if (state.tfSelected >= 0) {
        const renderer::OpacityPoint p = tf.opacities[size_t(state.tfSelected)];
        ImGui::Text("Opacity point %d of %zu", state.tfSelected + 1, tf.opacities.size());
        double value = p.value;
        if (numberField("Value", value, [&] {
                return ImGui::DragScalar("Value", ImGuiDataType_Double, &value, valueSpeed, nullptr, nullptr, "%.5g");
            })) {
            moveOpacityPoint(tf, state.tfSelected, value, p.opacity);
            state.tfEdited = changed = true;
        }
        numberHint("In the data's own units; a point stays between its neighbours");
        double opacity = p.opacity;
        const double zero = 0.0, one = 1.0;
        if (numberField("Extinction", opacity, [&] {
                return ImGui::SliderScalar("Extinction", ImGuiDataType_Double, &opacity, &zero, &one, "%.4g",
                                           axis == OpacityAxis::Log ? ImGuiSliderFlags_Logarithmic : 0);
            })) {
            moveOpacityPoint(tf, state.tfSelected, p.value, opacity);
            state.tfEdited = changed = true;
        }
        numberHint("Extinction per voxel length at density 1; 0: voxels of this value are never drawn");
        ImGui::BeginDisabled(tf.opacities.size() <= 2);
        if (ImGui::Button("Remove point") && removeOpacityPoint(tf, state.tfSelected)) {
            state.tfSelected = -1;
            state.tfEdited = changed = true;
        }
        ImGui::EndDisabled();
    } else if (state.tfColourSelected >= 0) {
        renderer::ColourPoint& p = tf.colours[size_t(state.tfColourSelected)];
        ImGui::Text("Colour stop %d of %zu", state.tfColourSelected + 1, tf.colours.size());
        double value = p.value;
        if (numberField("Value", value, [&] {
                return ImGui::DragScalar("Value", ImGuiDataType_Double, &value, valueSpeed, nullptr, nullptr, "%.5g");
            })) {
            moveColourStop(tf, state.tfColourSelected, value);
            state.tfEdited = changed = true;
        }
        numberHint("In the data's own units; a stop stays between its neighbours");
        float colour[3] = {float(p.colour.r), float(p.colour.g), float(p.colour.b)};
        if (ImGui::ColorEdit3("Colour", colour, ImGuiColorEditFlags_Float)) {
            for (int c = 0; c < 3; ++c) p.colour[c] = std::clamp(double(colour[c]), 0.0, 1.0);
            state.tfEdited = changed = true;
        }
        ImGui::BeginDisabled(tf.colours.size() <= 2);
        if (ImGui::Button("Remove stop") && removeColourStop(tf, state.tfColourSelected)) {
            state.tfColourSelected = -1;
            state.tfEdited = changed = true;
        }
        ImGui::EndDisabled();
    } else {
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
        textWrapped("Click a point on the curve (opacity) or a stop under the colour bar (colour) to edit it, or "
                    "empty space to add one; right-click one to remove it");
        ImGui::PopStyleColor();
    }

    // 5. The whole TF: Shift (drag: every point moves by the offset) and Rescale (its extent onto a range).
    ImGui::Spacing();
    const renderer::TfExtent extent = renderer::extentOf(tf);
    ImGui::Text("Points span %.5g .. %.5g", extent.lo, extent.hi);
    double shift = state.tfShift;
    if (ImGui::DragScalar("Shift", ImGuiDataType_Double, &shift, valueSpeed, nullptr, nullptr, "%+.5g")) {
        tf = renderer::shifted(tf, shift - state.tfShift);
        state.tfShift = shift;
        state.tfEdited = changed = true;
    }
    if (!ImGui::IsItemActive()) state.tfShift = 0.0;
    numberHint("Drag to move every colour stop and opacity point by the same amount (data units)");
    ImGui::TextUnformatted("Rescale to");
    const std::pair<RescaleTarget, renderer::ValueRange> targets[] = {{RescaleTarget::DataRange, view.dataRange},
                                                                      {RescaleTarget::Window, view.window},
                                                                      {RescaleTarget::Percentile, view.percentile},
                                                                      {RescaleTarget::Visible, view.visible}};
    for (const auto& [target, range] : targets) {
        ImGui::SameLine();
        ImGui::BeginDisabled(!(range.hi > range.lo));
        if (ImGui::SmallButton(rescaleTargetName(target))) {
            tf = renderer::rescaled(tf, range.lo, range.hi);
            state.tfEdited = changed = true;
        }
        ImGui::EndDisabled();
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
            ImGui::SetTooltip("Map the points' span (%.5g .. %.5g) onto %.5g .. %.5g, the others in proportion", extent.lo,
                              extent.hi, double(range.lo), double(range.hi));
    }

    // 6. Files: load replaces the curve; save writes the points (atomically) and names the TF after the file.
    ImGui::Spacing();
    pathField(
        "File", state.tfFile, FileKind::TransferFunction, state,
        "A TF file (JSON): the format of assets/presets/*.json and of --tf FILE; a ParaView preset (JSON);\n"
        "or 3D Slicer's presets.xml, its first preset or FILE.xml#NAME");
    if (ImGui::Button("Load") || takePendingFile(state, FileAction::LoadTransferFunction)) {
        try {
            std::vector<std::string> notes; // what an import leaves out, in the corner
            replace(renderer::inDataUnits(renderer::transferFunctionFromSpec(state.tfFile, &notes), window));
            noteRecentFile(state, FileKind::TransferFunction, state.tfFile);
            if (!notes.empty())
                state.saveNotice = SaveNotice{.text = notes.front(), .folder = {}, .shownAtS = -1.0};
        } catch (const renderer::LoadError& e) {
            state.errorMessage = e.what();
        } catch (const renderer::RenderError& e) { // a name that is no preset and no file
            state.errorMessage = e.what();
        }
    }
    ImGui::SameLine();
    if (ImGui::Button("Save")) {
        renderer::TransferFunction named = tf;
        named.name = std::filesystem::path(state.tfFile).stem().string();
        try {
            renderer::saveTransferFunction(named, state.tfFile);
            tf.name = named.name;
            state.tfGestureStart->name = named.name;   // naming is not an edit to undo
            state.tfEdited = false;
            state.saveNotice = savedNotice(state.tfFile);
            noteRecentFile(state, FileKind::TransferFunction, state.tfFile);
        } catch (const renderer::LoadError& e) {
            state.errorMessage = e.what();
        }
    }
    // 7. Undo and redo: the buttons, and Ctrl+Z / Ctrl+Y (or Ctrl+Shift+Z) while the panel has focus.
    ImGui::SameLine();
    const ImGuiIO& keys = ImGui::GetIO();
    const bool focused = ImGui::IsWindowFocused(ImGuiFocusedFlags_RootAndChildWindows) && !keys.WantTextInput;
    const bool ctrlZ = focused && keys.KeyCtrl && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Z), false);
    const bool ctrlY = focused && keys.KeyCtrl && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Y), false);
    auto step = [&](bool redo) {
        if (redo ? state.tfHistory.redoInto(tf) : state.tfHistory.undoInto(tf)) {
            state.tfGestureStart = tf;
            state.tfSelected = state.tfColourSelected = -1;
            state.tf2d.selected = -1;
            state.tfEdited = changed = true;
        }
    };
    ImGui::BeginDisabled(state.tfHistory.undo.empty());
    if (ImGui::Button("Undo") || (ctrlZ && !keys.KeyShift)) step(false);
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(state.tfHistory.redo.empty());
    if (ImGui::Button("Redo") || ctrlY || (ctrlZ && keys.KeyShift)) step(true);
    ImGui::EndDisabled();
    // 8. On the Undo row (closed, the panel keeps its height, so nothing above moves): the Gallery button
    //    and the collapsible gradient opacity curve (gradient_opacity_curve.cpp); the gallery's thumbnails
    //    under them while open.
    ImGui::SameLine();
    if (state.tfGalleryOpen) ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(ImGuiCol_ButtonActive));
    const bool toggled = ImGui::Button("Gallery");
    if (state.tfGalleryOpen) ImGui::PopStyleColor();
    if (toggled) state.tfGalleryOpen = !state.tfGalleryOpen;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%s the thumbnails of the presets, each drawn on this volume; click one to apply it",
                          state.tfGalleryOpen ? "Hide" : "Show");
    ImGui::SameLine();
    if (drawGradientOpacityCurve(tf, state.tfGradient, view.gradients)) state.tfEdited = changed = true;
    if (state.tfGalleryOpen)
        if (const std::optional<std::string> name = drawGallery(view.gallery)) try {
                replace(renderer::inDataUnits(renderer::builtinPreset(*name), window));
            } catch (const std::exception& e) { // a bundled file that is not a TF, or one since removed
                state.errorMessage = e.what();
            }
    // 9. Under them: the 2D transfer function's widgets over (value, gradient magnitude) (tf2d_editor.cpp).
    if (drawTf2dSection(tf, state.tf2d,
                        {.axes = {.window = window, .maxMagnitude = view.gradients.maxMagnitude},
                         .histogram = view.histogram2d,
                         .histogramWindow = view.histogram2dWindow}))
        state.tfEdited = changed = true;
    // A gesture ends when no widget is held: a drag released, a field left, or an instant edit (a
    // preset, a file, a removal). What it changed becomes one undo step.
    if (!ImGui::IsAnyItemActive()) {
        if (tf != *state.tfGestureStart) state.tfHistory.record(*state.tfGestureStart);
        state.tfGestureStart = tf;
    }
    ImGui::PopItemWidth();
    return changed;
}

} // namespace ui
