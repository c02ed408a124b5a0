// The save confirmation's text, fade and window; what was saved is the caller's business.
#include "ui/save_notice.h"

#include <imgui.h>

#include <algorithm>

namespace ui {

SaveNotice savedNotice(const std::filesystem::path& file, const std::string& detail) {
    SaveNotice notice;
    notice.text = "Saved " + file.filename().string() + (detail.empty() ? "" : " (" + detail + ")");
    const std::filesystem::path folder = file.parent_path();
    notice.folder = "in " + (folder.empty() ? std::string("the current folder") : folder.string());
    return notice;
}

float saveNoticeAlpha(double sinceS) {
    if (sinceS <= SaveNotice::kShownS) return 1.0f;
    return float(std::clamp(1.0 - (sinceS - SaveNotice::kShownS) / SaveNotice::kFadeS, 0.0, 1.0));
}

void drawSaveNotice(SaveNotice& notice) {
    if (notice.text.empty()) return;
    const double now = ImGui::GetTime();
    if (notice.shownAtS < 0.0) notice.shownAtS = now;
    const float alpha = saveNoticeAlpha(now - notice.shownAtS);
    if (alpha <= 0.0f) {
        notice = {};
        return;
    }
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float margin = ImGui::GetFontSize();
    ImGui::SetNextWindowPos(ImVec2(viewport->WorkPos.x + viewport->WorkSize.x - margin,
                                   viewport->WorkPos.y + viewport->WorkSize.y - margin),
                            ImGuiCond_Always, ImVec2(1.0f, 1.0f));
    ImGui::SetNextWindowBgAlpha(0.85f * alpha);
    ImGui::PushStyleVar(ImGuiStyleVar_Alpha, alpha);
    constexpr ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                       ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_NoFocusOnAppearing |
                                       ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoSavedSettings;
    if (ImGui::Begin("##save_notice", nullptr, flags)) {
        ImGui::TextColored(ImVec4(0.55f, 0.9f, 0.55f, 1.0f), "%s", notice.text.c_str());
        ImGui::TextDisabled("%s", notice.folder.c_str());
    }
    ImGui::End();
    ImGui::PopStyleVar();
}

} // namespace ui
