// Small ImGui helpers every panel file shares.
#pragma once
#include <imgui.h>

#include <string>

namespace ui {

// A tooltip on the item just drawn: says what a setting does, not what it is called.
inline void hint(const char* text) {
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
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

inline void sectionTitle(const char* title) {
    ImGui::Spacing();
    ImGui::TextDisabled("%s", title);
    ImGui::Separator();
}

} // namespace ui
