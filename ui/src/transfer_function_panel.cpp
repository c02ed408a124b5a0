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

namespace ui {

namespace {

constexpr float kPointRadiusPx = 5.0f;
constexpr float kPickRadiusPx = 8.0f;   // a little more than the drawn dot: easy to grab

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

// The curve: the TF's colour filled up to its opacity, the polyline, and the points (the selected one
// larger, outlined in the accent colour).
void drawCurve(ImDrawList* draw, const Rect& canvas, const renderer::TransferFunction& tf, int selected,
               OpacityAxis axis) {
    std::vector<ImVec2> line;
    for (float x = 0.0f; x < canvas.w; x += 2.0f) {
        const double value = (double(x) + 1.0) / canvas.w;
        const glm::dvec4 c = renderer::evaluate(tf, value);
        const float top = tfToCanvas(canvas, value, c.a, axis).y;
        draw->AddRectFilled(ImVec2(canvas.x + x, top), ImVec2(canvas.x + std::min(x + 2.0f, canvas.w), canvas.bottom()),
                            colourOf(glm::dvec3(c), 0.55f));
        line.emplace_back(canvas.x + x + 1.0f, top);
    }
    const auto& pts = tf.points;
    // Linear: straight segments between the points; log: the segments (linear in opacity) bend, so the
    // line follows the sampled curve.
    if (axis == OpacityAxis::Log)
        draw->AddPolyline(line.data(), int(line.size()), IM_COL32(235, 235, 240, 255), 0, 1.5f);
    for (size_t i = 0; i + 1 < pts.size() && axis == OpacityAxis::Linear; ++i) {
        const CanvasPoint a = tfToCanvas(canvas, pts[i].value, pts[i].opacity);
        const CanvasPoint b = tfToCanvas(canvas, pts[i + 1].value, pts[i + 1].opacity);
        draw->AddLine(ImVec2(a.x, a.y), ImVec2(b.x, b.y), IM_COL32(235, 235, 240, 255), 1.5f);
    }
    // The axis: what it measures, and on a log axis a line and a label a decade.
    const ImU32 label = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    if (axis == OpacityAxis::Log)
        for (int d = 1; d < int(kLogOpacityDecades); ++d) {
            const double at = std::pow(10.0, -d);
            const float y = tfToCanvas(canvas, 0.0, at, axis).y;
            draw->AddLine(ImVec2(canvas.x, y), ImVec2(canvas.right(), y), IM_COL32(255, 255, 255, 30));
            char text[16];
            std::snprintf(text, sizeof text, "%g", at);
            draw->AddText(ImVec2(canvas.x + 3.0f, y - ImGui::GetFontSize()), label, text);
        }
    draw->AddText(ImVec2(canvas.x + 3.0f, canvas.y + 2.0f), label,
                  axis == OpacityAxis::Log ? "extinction / voxel length (log)" : "extinction / voxel length");
    for (size_t i = 0; i < pts.size(); ++i) {
        const CanvasPoint p = tfToCanvas(canvas, pts[i].value, pts[i].opacity, axis);
        const bool chosen = int(i) == selected;
        const float r = chosen ? kPointRadiusPx + 2.0f : kPointRadiusPx;
        draw->AddCircleFilled(ImVec2(p.x, p.y), r, colourOf(pts[i].colour));
        draw->AddCircle(ImVec2(p.x, p.y), r, chosen ? IM_COL32(255, 200, 80, 255) : IM_COL32(240, 240, 240, 255), 0,
                        chosen ? 2.0f : 1.0f);
    }
}

} // namespace

bool drawTransferFunctionPanel(EditorState& state, const TransferFunctionView& view) {
    renderer::TransferFunction& tf = state.tf;
    bool changed = false;
    auto replace = [&](renderer::TransferFunction loaded) {
        tf = std::move(loaded);
        state.tfSelected = -1;
        state.tfEdited = false;
        changed = true;
    };
    if (state.tfSelected >= int(tf.points.size())) state.tfSelected = -1;
    if (!state.tfGestureStart) state.tfGestureStart = tf;

    // 1. Preset.
    sectionTitle("Transfer function");
    const std::string shown = tf.name + (state.tfEdited ? " (edited)" : "");
    if (ImGui::BeginCombo("Preset", shown.c_str())) {
        for (const std::string& name : renderer::builtinPresetNames())
            if (ImGui::Selectable(name.c_str(), name == tf.name && !state.tfEdited)) try {
                    replace(renderer::builtinPreset(name));
                } catch (const renderer::LoadError& e) {   // a bundled file that is not a TF
                    state.errorMessage = e.what();
                }
        ImGui::EndCombo();
    }
    hint("Transfer functions: value -> colour and extinction; the built-in ones, then each NAME.json in\n"
         "assets/presets. Picking one replaces the curve below");

    // 2. The curve. One button over the canvas takes left presses (pick or add, then drag) and right
    //    clicks (remove).
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const Rect canvas{origin.x, origin.y, std::max(ImGui::GetContentRegionAvail().x, 32.0f),
                      ImGui::GetFontSize() * 11.0f};
    ImGui::InvisibleButton("##tf_canvas", ImVec2(canvas.w, canvas.h),
                           ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
    const ImGuiIO& io = ImGui::GetIO();
    const CanvasPoint mouse{io.MousePos.x, io.MousePos.y};
    const OpacityAxis axis = state.tfLogOpacity ? OpacityAxis::Log : OpacityAxis::Linear;
    if (ImGui::IsItemActivated() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        int picked = pickControlPoint(tf, canvas, mouse, kPickRadiusPx, axis);
        if (picked < 0) {   // empty space: a new point under the mouse
            double value = 0, opacity = 0;
            canvasToTf(canvas, mouse, value, opacity, axis);
            picked = insertControlPoint(tf, value, opacity);
            state.tfEdited = changed = true;
        }
        const CanvasPoint p =
            tfToCanvas(canvas, tf.points[size_t(picked)].value, tf.points[size_t(picked)].opacity, axis);
        state.tfSelected = picked;
        state.tfGrabDx = p.x - mouse.x, state.tfGrabDy = p.y - mouse.y;
    } else if (ImGui::IsItemActive() && ImGui::IsMouseDown(ImGuiMouseButton_Left) && state.tfSelected >= 0 &&
               (io.MouseDelta.x != 0.0f || io.MouseDelta.y != 0.0f)) {
        double value = 0, opacity = 0;
        canvasToTf(canvas, {mouse.x + state.tfGrabDx, mouse.y + state.tfGrabDy}, value, opacity, axis);
        const renderer::ControlPoint before = tf.points[size_t(state.tfSelected)];
        moveControlPoint(tf, state.tfSelected, value, opacity);
        const renderer::ControlPoint& after = tf.points[size_t(state.tfSelected)];
        if (after.value != before.value || after.opacity != before.opacity) state.tfEdited = changed = true;
    }
    if (ImGui::IsItemClicked(ImGuiMouseButton_Right)) {
        const int picked = pickControlPoint(tf, canvas, mouse, kPickRadiusPx, axis);
        if (removeControlPoint(tf, picked)) {
            state.tfSelected = -1;
            state.tfEdited = changed = true;
        }
    }
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(ImVec2(canvas.x, canvas.y), ImVec2(canvas.right(), canvas.bottom()),
                        ImGui::GetColorU32(ImGuiCol_FrameBg));
    if (view.histogram) drawHistogram(draw, canvas, *view.histogram, view.window);
    drawCurve(draw, canvas, tf, state.tfSelected, axis);
    // The value of the voxel the mouse points at in the viewport, where it falls on this axis; none
    // outside the window (fromDataUnits would clamp it to an end).
    if (state.probe && state.probe->value >= view.window.lo && state.probe->value <= view.window.hi) {
        const float x = tfToCanvas(canvas, fromDataUnits(state.probe->value, view.window), 0.0).x;
        draw->AddLine(ImVec2(x, canvas.y), ImVec2(x, canvas.bottom()), kProbeMarkerColour, 2.0f);
    }
    if (ImGui::IsItemHovered()) {
        const int over = pickControlPoint(tf, canvas, mouse, kPickRadiusPx, axis);
        double value = 0, opacity = 0;
        canvasToTf(canvas, mouse, value, opacity, axis);
        if (over >= 0) value = tf.points[size_t(over)].value, opacity = tf.points[size_t(over)].opacity;
        else opacity = renderer::evaluate(tf, value).a;
        ImGui::SetTooltip("%s %.5g (data units), extinction %.4g per voxel length at density 1\n%s",
                          over >= 0 ? "point at" : "value",
                          toDataUnits(value, view.window), opacity,
                          over >= 0 ? "drag to move, right-click to remove" : "click to add a point here");
    }
    // The colour bar: the TF's colour at each value, whatever its opacity.
    const float barY = canvas.bottom() + 3.0f, barH = ImGui::GetFontSize() * 0.7f;
    for (float x = 0.0f; x < canvas.w; x += 2.0f)
        draw->AddRectFilled(ImVec2(canvas.x + x, barY), ImVec2(canvas.x + std::min(x + 2.0f, canvas.w), barY + barH),
                            colourOf(glm::dvec3(renderer::evaluate(tf, (double(x) + 1.0) / canvas.w))));
    ImGui::Dummy(ImVec2(canvas.w, barH + 3.0f));
    ImGui::TextDisabled("%.5g", double(view.window.lo));
    // Between the window's ends, as tall as their text (no frame padding), so nothing below moves.
    ImGui::SameLine(0.3f * canvas.w);
    ImGui::PushStyleVar(ImGuiStyleVar_FramePadding, ImVec2(2.0f, 0.0f));
    ImGui::Checkbox("log axis", &state.tfLogOpacity);
    ImGui::PopStyleVar();
    hint("The curve's axis in decades (1 down to 0.001): room for the faint values air and skin need.\n"
         "A point dragged to the baseline is exactly 0, to the top exactly 1");
    const std::string hiText = [&] {
        char text[32];
        std::snprintf(text, sizeof text, "%.5g", double(view.window.hi));
        return std::string(text);
    }();
    ImGui::SameLine(std::max(canvas.w - ImGui::CalcTextSize(hiText.c_str()).x, 0.0f) + ImGui::GetStyle().WindowPadding.x);
    ImGui::TextDisabled("%s", hiText.c_str());

    // 3. The selected point's fields: value in data units, opacity, colour; remove.
    ImGui::PushItemWidth(-ImGui::GetFontSize() * 6.0f); // room for "Extinction"
    if (state.tfSelected >= 0) {
        renderer::ControlPoint& p = tf.points[size_t(state.tfSelected)];
        ImGui::Text("Point %d of %zu", state.tfSelected + 1, tf.points.size());
        double data = toDataUnits(p.value, view.window);
        const double lo = view.window.lo, hi = view.window.hi;
        if (numberField("Value", data, [&] {
                return ImGui::DragScalar("Value", ImGuiDataType_Double, &data, float((hi - lo) / 1000.0), &lo,
                                         &hi, "%.5g");
            })) {
            moveControlPoint(tf, state.tfSelected, fromDataUnits(data, view.window), p.opacity);
            state.tfEdited = changed = true;
        }
        numberHint("In the data's own units; a point stays between its neighbours");
        double opacity = p.opacity;
        const double zero = 0.0, one = 1.0;
        if (numberField("Extinction", opacity, [&] {
                return ImGui::SliderScalar("Extinction", ImGuiDataType_Double, &opacity, &zero, &one, "%.4g",
                                           axis == OpacityAxis::Log ? ImGuiSliderFlags_Logarithmic : 0);
            })) {
            moveControlPoint(tf, state.tfSelected, p.value, opacity);
            state.tfEdited = changed = true;
        }
        numberHint("Extinction per voxel length at density 1; 0: voxels of this value are never drawn");
        float colour[3] = {float(p.colour.r), float(p.colour.g), float(p.colour.b)};
        if (ImGui::ColorEdit3("Colour", colour, ImGuiColorEditFlags_Float)) {
            for (int c = 0; c < 3; ++c) p.colour[c] = std::clamp(double(colour[c]), 0.0, 1.0);
            state.tfEdited = changed = true;
        }
        ImGui::BeginDisabled(tf.points.size() <= 2);
        if (ImGui::Button("Remove point") && removeControlPoint(tf, state.tfSelected)) {
            state.tfSelected = -1;
            state.tfEdited = changed = true;
        }
        ImGui::EndDisabled();
    } else {
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
        textWrapped("Click a point to edit it, or empty space to add one; right-click a point to remove it");
        ImGui::PopStyleColor();
    }

    // 4. Files: load replaces the curve; save writes the points (atomically) and names the TF after the file.
    ImGui::Spacing();
    pathField("File", state.tfFile, FileKind::TransferFunction, state,
              "A TF file (JSON): the format of assets/presets/*.json and of --tf FILE");
    if (ImGui::Button("Load") || takePendingFile(state, FileAction::LoadTransferFunction)) {
        try {
            replace(renderer::loadTransferFunction(state.tfFile));
            noteRecentFile(state, FileKind::TransferFunction, state.tfFile);
        } catch (const renderer::LoadError& e) {
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
    // 5. Undo and redo: the buttons, and Ctrl+Z / Ctrl+Y (or Ctrl+Shift+Z) while the panel has focus.
    ImGui::SameLine();
    const ImGuiIO& keys = ImGui::GetIO();
    const bool focused = ImGui::IsWindowFocused(ImGuiFocusedFlags_RootAndChildWindows) && !keys.WantTextInput;
    const bool ctrlZ = focused && keys.KeyCtrl && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Z), false);
    const bool ctrlY = focused && keys.KeyCtrl && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Y), false);
    auto step = [&](bool redo) {
        if (redo ? state.tfHistory.redoInto(tf) : state.tfHistory.undoInto(tf)) {
            state.tfGestureStart = tf;
            state.tfSelected = -1;
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
