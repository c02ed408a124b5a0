// Numeric fields that take a plain click as "type a value here", as spreadsheets and ParaView do.
// ImGui 1.86 sets a slider to wherever a click lands and types only on Ctrl+click; every numeric field in
// the editor goes through numberField() instead, so a press without a drag opens the text input and a
// drag still changes the value.
#pragma once
#include <imgui.h>

namespace ui {

namespace detail {
// Before the widget: opens its text input when the last plain click, a frame ago, was on it.
void beginNumberField(ImGuiID id);
// After it: until the pointer moves past the drag threshold the value stays what it was at the press
// (a slider would jump to the click); a release without a drag asks for the text input next frame.
// `before` is the value the widget was drawn with; returns whether the value changed.
bool endNumberField(ImGuiID id, double before, double& value, bool changed);
} // namespace detail

// Draws a numeric widget with `label` (`draw` calls ImGui's SliderScalar, DragFloat, ... on `value`) so
// that a plain click types into it. Returns what the widget returns, less a slider's jump on a click.
template <class T, class Draw> bool numberField(const char* label, T& value, Draw draw) {
    const ImGuiID id = ImGui::GetID(label);
    detail::beginNumberField(id);
    const T before = value;
    bool changed = draw();
    double now = double(value);
    changed = detail::endNumberField(id, double(before), now, changed);
    value = T(now); // float and int round-trip through double exactly
    return changed;
}

// The pointer distance (pixels) under which a press and release is a click, not a drag: ImGui's drag
// fields start moving at half the drag threshold, so a shorter move never changed a value.
float numberFieldClickSlopPx();

} // namespace ui
