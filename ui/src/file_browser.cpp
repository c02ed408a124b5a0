// The file browser popup behind every path field (file_browser.h). Listing and filtering are
// file_listing.cpp's; this file lays them out and turns clicks into a chosen path.
#include "ui/file_browser.h"

#include "renderer/errors.h"
#include "ui/editor_state.h"
#include "widgets.h"

#include <imgui.h>

#include <cstdio>

namespace ui {

namespace fs = std::filesystem;

namespace {

// Where the browser opens for a field holding `path`: the folder of the file named, else the folder
// named, else the working folder.
fs::path startFolder(const std::string& path) {
    std::error_code ec;
    if (path.empty()) return fs::current_path(ec);
    const fs::path p(path);
    if (fs::is_directory(p, ec)) return p;
    const fs::path parent = p.parent_path();
    if (!parent.empty() && fs::is_directory(parent, ec)) return parent;
    return fs::current_path(ec);
}

std::string sizeText(std::uintmax_t bytes) {
    char text[32];
    if (bytes >= (std::uintmax_t(1) << 30))
        std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(1 << 30));
    else if (bytes >= (1u << 20))
        std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / double(1 << 20));
    else if (bytes >= (1u << 10))
        std::snprintf(text, sizeof text, "%.1f KiB", double(bytes) / double(1 << 10));
    else
        std::snprintf(text, sizeof text, "%ju B", bytes);
    return text;
}

// The popup's body; returns the path chosen, or "" while none is.
std::string drawBrowser(FileBrowserState& b, const RecentFiles& recent) {
    if (b.stale) {
        b.listing = listFolder(b.listing.folder, b.kind);
        b.stale = false;
    }
    std::string chosen;
    // 1. Where we are, and up.
    ImGui::BeginDisabled(b.listing.folder == b.listing.folder.root_path());
    if (ImGui::Button("Up")) {
        b.listing.folder = b.listing.folder.parent_path();
        b.stale = true;
    }
    ImGui::EndDisabled();
    hint("The parent folder");
    ImGui::SameLine();
    ImGui::TextUnformatted(b.listing.folder.string().c_str());
    // 2. Recent files of this kind.
    const std::vector<std::string>& recentPaths = recent.of(b.kind);
    ImGui::BeginDisabled(recentPaths.empty());
    if (ImGui::BeginCombo("Recent", recentPaths.empty() ? "(none yet)" : "(pick one)",
                          ImGuiComboFlags_HeightLarge)) {
        for (const std::string& path : recentPaths)
            if (ImGui::Selectable(path.c_str())) chosen = path;
        ImGui::EndCombo();
    }
    ImGui::EndDisabled();
    // 3. The folder's entries: a click on a folder enters it, on a file picks it, a double-click opens it.
    std::string shown = "Folders and ";
    for (const std::string& ext : fileKindExtensions(b.kind))
        shown += ext + " ";
    shown += "files";
    if (b.listing.hiddenFiles)
        shown += " (" + std::to_string(b.listing.hiddenFiles) + (b.listing.hiddenFiles == 1 ? " other" : " others") +
                 " hidden)";
    textDisabledWrapped("%s", shown.c_str());
    if (!b.listing.error.empty())
        textColouredWrapped(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", b.listing.error.c_str());
    const float footer = ImGui::GetFrameHeightWithSpacing() * 2.0f + ImGui::GetStyle().ItemSpacing.y;
    ImGui::BeginChild("##entries", ImVec2(0.0f, -footer), true);
    for (const FolderEntry& entry : b.listing.entries) {
        if (entry.folder) {
            if (ImGui::Selectable((entry.name + "/").c_str())) {
                b.listing.folder /= entry.name;
                b.stale = true;
            }
            continue;
        }
        if (ImGui::Selectable(entry.name.c_str(), b.name == entry.name,
                              ImGuiSelectableFlags_AllowDoubleClick)) {
            b.name = entry.name;
            if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left))
                chosen = (b.listing.folder / entry.name).string();
        }
        const std::string size = sizeText(entry.bytes);
        ImGui::SameLine(ImGui::GetContentRegionMax().x - ImGui::CalcTextSize(size.c_str()).x);
        ImGui::TextDisabled("%s", size.c_str());
    }
    ImGui::EndChild();
    // 4. The file name (a click fills it; type one to save under a new name), then choose or cancel.
    inputPath("File name", b.name);
    ImGui::BeginDisabled(b.name.empty());
    if (ImGui::Button("Choose")) chosen = (b.listing.folder / b.name).string();
    ImGui::EndDisabled();
    if (b.kind == FileKind::Volume) {
        ImGui::SameLine();
        if (ImGui::Button("This folder as slices")) chosen = b.listing.folder.string();
        hint("The folder's .tif/.png slices as one volume, sorted by the number in their names");
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
    return chosen;
}

} // namespace

bool pathField(const char* label, std::string& path, FileKind kind, EditorState& state, const char* tooltip) {
    ImGui::PushID(label);
    const ImGuiStyle& style = ImGui::GetStyle();
    const float button =
        ImGui::CalcTextSize("Browse").x + 2.0f * style.FramePadding.x + style.ItemInnerSpacing.x;
    ImGui::SetNextItemWidth(ImGui::CalcItemWidth() - button);
    inputPath("##path", path);
    hint(tooltip);
    ImGui::SameLine(0.0f, style.ItemInnerSpacing.x);
    const char* popup = "Choose a file";
    if (ImGui::Button("Browse")) {
        state.fileBrowser = FileBrowserState{};
        state.fileBrowser.kind = kind;
        state.fileBrowser.listing.folder = startFolder(path);
        state.fileBrowser.name = fs::path(path).filename().string();
        ImGui::OpenPopup(popup);
    }
    hint("Pick the file in a browser of the folders, with the recent files");
    ImGui::SameLine(0.0f, style.ItemInnerSpacing.x);
    ImGui::TextUnformatted(label); // the field's name, as ImGui draws a label (no "##" in these)
    bool picked = false;
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowSize(ImVec2(viewport->WorkSize.x * 0.5f, viewport->WorkSize.y * 0.6f),
                             ImGuiCond_Appearing);
    ImGui::SetNextWindowPos(viewport->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal(popup)) {
        const std::string chosen = drawBrowser(state.fileBrowser, state.recentFiles);
        if (!chosen.empty()) {
            path = chosen;
            picked = true;
            ImGui::CloseCurrentPopup();
        }
        ImGui::EndPopup();
    }
    ImGui::PopID();
    return picked;
}

void noteRecentFile(EditorState& state, FileKind kind, const fs::path& path) {
    addRecentFile(state.recentFiles, kind, path);
    if (state.configDir.empty()) return;
    try {
        saveRecentFiles(state.recentFiles, state.configDir);
    } catch (const renderer::LoadError& e) {
        static bool told = false; // once a run: the list still works in memory
        if (!told) std::fprintf(stderr, "splatlab editor: recent files not kept: %s\n", e.what());
        told = true;
    }
}

} // namespace ui
