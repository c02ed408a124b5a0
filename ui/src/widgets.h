// Small ImGui helpers every panel file shares.
#pragma once
#include <imgui.h>

namespace ui {

// A tooltip on the item just drawn: says what a setting does, not what it is called.
inline void hint(const char* text) {
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

inline void sectionTitle(const char* title) {
    ImGui::Spacing();
    ImGui::TextDisabled("%s", title);
    ImGui::Separator();
}

} // namespace ui
