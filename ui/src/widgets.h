// Small ImGui helpers every panel file shares.
#pragma once
#include "renderer/gl/splat_renderer.h"
#include "ui/editor_state.h"
#include "ui/number_field.h"
#include "ui/text_wrap.h"
#include "ui/tf_editor.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cstdarg>
#include <cstdio>
#include <string>

namespace ui {

// A canvas at the cursor, `width` (0: the panel's) by `height` px, under one button that takes left
// presses (pick or add, then drag) and right clicks (remove): the curve editors' gestures. Gives its
// rectangle, the mouse and whether the mouse moved this frame; ImGui::IsItem* then ask about the button.
struct CanvasInput {
    Rect rect;
    CanvasPoint mouse;
    bool moved = false;
};
inline CanvasInput canvasInput(const char* id, float height, float width = 0.0f) {
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const Rect rect{origin.x, origin.y, width > 0.0f ? width : std::max(ImGui::GetContentRegionAvail().x, 32.0f),
                    height};
    ImGui::InvisibleButton(id, ImVec2(rect.w, rect.h), ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
    const ImGuiIO& io = ImGui::GetIO();
    return {rect, CanvasPoint{io.MousePos.x, io.MousePos.y}, io.MouseDelta.x != 0.0f || io.MouseDelta.y != 0.0f};
}

// A tooltip on the item just drawn: says what a setting does, not what it is called. Disabled items
// keep theirs, since what a setting would do is also why it is greyed out.
inline void hint(const char* text) {
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("%s", text);
}

// hint() for a numeric field drawn through numberField(), saying how to use it.
inline void numberHint(const char* text) {
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("%s\nClick to type a value, drag to change it", text);
}

// A slider for a double through numberField() (a press without a drag types a value).
inline bool sliderDouble(const char* label, double& value, double lo, double hi, const char* format,
                         ImGuiSliderFlags flags = 0) {
    return numberField(label, value, [&] {
        return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, format, flags);
    });
}

// ImGui 1.86's InputText takes a fixed buffer; this grows the std::string as the user types.
inline bool inputPath(const char* label, std::string& text) {
    auto resize = [](ImGuiInputTextCallbackData* data) {
        if (data->EventFlag == ImGuiInputTextFlags_CallbackResize) {
            auto* s = static_cast<std::string*>(data->UserData);
            s->resize(size_t(data->BufTextLen));
            data->Buf = s->data();
        }
        return 0;
    };
    return ImGui::InputText(label, text.data(), text.capacity() + 1, ImGuiInputTextFlags_CallbackResize, resize,
                            &text);
}

// A combo over an enum's values, labelled with the renderer's own names for them.
template <class E, size_t N>
inline bool enumCombo(const char* label, E& value, const std::array<E, N>& options, const char* (*nameOf)(E)) {
    bool changed = false;
    if (ImGui::BeginCombo(label, nameOf(value))) {
        for (E option : options) {
            const bool selected = option == value;
            if (ImGui::Selectable(nameOf(option), selected) && !selected) value = option, changed = true;
            if (selected) ImGui::SetItemDefaultFocus();
        }
        ImGui::EndCombo();
    }
    return changed;
}

// The colour of a GPU pass (renderer::GpuPass) in the pass bar and the Performance chart.
inline ImColor passColour(int pass, int passes) { return ImColor::HSV(float(pass) / float(passes), 0.55f, 0.85f); }

// Puts the next item of `text`'s width (plus `extra`, e.g. a radio button's circle) on the current line
// when it fits the region, else on a new one.
inline void sameLineIfFits(const char* text, float extra = 0.0f) {
    const float needed = ImGui::CalcTextSize(text).x + extra + ImGui::GetStyle().ItemSpacing.x;
    ImGui::SameLine();
    if (ImGui::GetContentRegionAvail().x < needed) ImGui::NewLine();
}

// Text that wraps at the region's edge, between words only (wrapAtSpaces: ImGui's own wrapping splits
// numbers at their decimal point). In a table cell the region can end a pixel or two past the cell's
// clip rectangle: the nearer edge is the one that counts.
inline void textWrappedV(const char* format, va_list args) {
    char text[1024];
    std::vsnprintf(text, sizeof text, format, args);
    const auto measure = [](std::string_view s) { return ImGui::CalcTextSize(s.data(), s.data() + s.size()).x; };
    const float visible = ImGui::GetWindowDrawList()->GetClipRectMax().x - ImGui::GetCursorScreenPos().x;
    const auto lines = wrapAtSpaces(text, std::min(ImGui::GetContentRegionAvail().x, visible), measure);
    // Lines of one text sit a line height apart, as ImGui's wrapping sets them; the item spacing follows the last.
    ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImVec2(ImGui::GetStyle().ItemSpacing.x, 0.0f));
    for (size_t i = 0; i < lines.size(); ++i) {
        if (i + 1 == lines.size()) ImGui::PopStyleVar();
        ImGui::TextUnformatted(lines[i].data(), lines[i].data() + lines[i].size());
    }
}

inline void textWrapped(const char* format, ...) IM_FMTARGS(1);
inline void textWrapped(const char* format, ...) {
    va_list args;
    va_start(args, format);
    textWrappedV(format, args);
    va_end(args);
}

// Text in `colour` that wraps at the region's edge, as textWrapped.
inline void textColouredWrappedV(const ImVec4& colour, const char* format, va_list args) {
    ImGui::PushStyleColor(ImGuiCol_Text, colour);
    textWrappedV(format, args);
    ImGui::PopStyleColor();
}
inline void textColouredWrapped(const ImVec4& colour, const char* format, ...) IM_FMTARGS(2);
inline void textColouredWrapped(const ImVec4& colour, const char* format, ...) {
    va_list args;
    va_start(args, format);
    textColouredWrappedV(colour, format, args);
    va_end(args);
}

// Disabled (grey) text that wraps at the region's edge, as textWrapped.
inline void textDisabledWrapped(const char* format, ...) IM_FMTARGS(1);
inline void textDisabledWrapped(const char* format, ...) {
    va_list args;
    va_start(args, format);
    textColouredWrappedV(ImGui::GetStyle().Colors[ImGuiCol_TextDisabled], format, args);
    va_end(args);
}

// A bullet and text that wraps at the region's edge, its later lines under its first.
inline void bulletWrapped(const char* format, ...) IM_FMTARGS(1);
inline void bulletWrapped(const char* format, ...) {
    ImGui::Bullet();
    ImGui::BeginGroup();   // the group's left edge is where the text starts
    va_list args;
    va_start(args, format);
    textWrappedV(format, args);
    va_end(args);
    ImGui::EndGroup();
}

// "label" then each pass that took time, "name ms" in its colour, wrapping at the region's edge.
inline void drawPassList(const char* label, const std::array<double, renderer::kGpuPasses>& passMs) {
    ImGui::TextUnformatted(label);
    for (int i = 0; i < renderer::kGpuPasses; ++i)
        if (const double ms = passMs[size_t(i)]; ms > 0.0) {
            char part[48];
            std::snprintf(part, sizeof part, "%s %.1f", renderer::gpuPassName(renderer::GpuPass(i)), ms);
            sameLineIfFits(part);
            ImGui::TextColored(passColour(i, renderer::kGpuPasses), "%s", part);
        }
}

// The button press a dropped file stands for (dropFile), once: true when `action` was pending.
inline bool takePendingFile(EditorState& state, FileAction action) {
    if (state.pendingFile != action) return false;
    state.pendingFile = FileAction::None;
    return true;
}

inline void sectionTitle(const char* title) {
    ImGui::Spacing();
    ImGui::TextDisabled("%s", title);
    ImGui::Separator();
}

} // namespace ui
