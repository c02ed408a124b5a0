// Small ImGui helpers every panel file shares.
#pragma once
#include "renderer/splat_renderer.h"

#include <imgui.h>

#include <array>
#include <cstdio>
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

// The colour of a GPU pass (renderer::GpuPass) in the pass bar and the Performance chart.
inline ImColor passColour(int pass, int passes) { return ImColor::HSV(float(pass) / float(passes), 0.55f, 0.85f); }

// Puts the next item of `text`'s width on the current line when it fits the region, else on a new one.
inline void sameLineIfFits(const char* text) {
    const float needed = ImGui::CalcTextSize(text).x + ImGui::GetStyle().ItemSpacing.x;
    ImGui::SameLine();
    if (ImGui::GetContentRegionAvail().x < needed) ImGui::NewLine();
}

// Disabled (grey) text that wraps at the region's edge.
inline void textDisabledWrapped(const char* text) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped("%s", text);
    ImGui::PopStyleColor();
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

inline void sectionTitle(const char* title) {
    ImGui::Spacing();
    ImGui::TextDisabled("%s", title);
    ImGui::Separator();
}

} // namespace ui
