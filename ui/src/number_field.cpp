// numberField's state between frames: which field was pressed, its value then, and which field opens
// its text input next frame. Only one item is active at a time, so one record serves every field.
#include "ui/number_field.h"

#include <imgui_internal.h>

namespace ui {

namespace {
struct NumberFieldPress {
    ImGuiID pressed = 0; // the field under a mouse press that has not become a drag yet
    double valueAtPress = 0.0;
    ImGuiID typeNext = 0; // the field a plain click released on: its text input opens ...
    int typeOnFrame = -1; // ... on this frame only, so a field hidden meanwhile never opens later
};
NumberFieldPress press;
} // namespace

float numberFieldClickSlopPx() { return ImGui::GetIO().MouseDragThreshold * 0.5f; }

namespace detail {

void beginNumberField(ImGuiID id) {
    ImGuiContext& g = *ImGui::GetCurrentContext();
    if (press.typeNext != id) return;
    if (press.typeOnFrame == g.FrameCount) {
        // What ImGui's own Tab-to-type sets: the widget takes this as a request for its text input.
        g.NavActivateInputId = id;
        g.NavActivateFlags = ImGuiActivateFlags_PreferInput;
    }
    press.typeNext = 0;
}

bool endNumberField(ImGuiID id, double before, double& value, bool changed) {
    const ImGuiIO& io = ImGui::GetIO();
    if (ImGui::TempInputIsActive(id)) return changed; // typing (Ctrl+click, Tab or a plain click)
    if (ImGui::IsItemActivated() && io.MouseDown[0]) press = {id, before, 0, -1};
    if (press.pressed != id) return changed;
    const bool dragged = ImGui::IsMouseDragPastThreshold(ImGuiMouseButton_Left, numberFieldClickSlopPx());
    if (dragged) {
        if (!ImGui::IsItemActive()) press.pressed = 0;
        return changed;
    }
    value = press.valueAtPress; // not a drag (yet): no jump to where the click landed
    if (!ImGui::IsItemActive()) {
        press.pressed = 0;
        if (io.MouseReleased[0]) {
            press.typeNext = id;
            press.typeOnFrame = ImGui::GetFrameCount() + 1;
        }
    }
    return value != before;
}

} // namespace detail

} // namespace ui
