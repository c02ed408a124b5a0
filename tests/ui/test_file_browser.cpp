// The file browser popup driven with synthetic clicks: Browse beside the Volume field, into a folder,
// a double-click on a volume: the field holds its path and the panel asks the app to open it.
#include "imgui_null.h"
#include "renderer/io/volume_io.h"
#include "test_paths.h"
#include "ui/file_browser.h"
#include "ui/panels.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

namespace {

namespace fs = std::filesystem;

class FileBrowser : public ImGuiNull {
  protected:
    ui::EditorState state;
    bool openVolume = false;
    std::function<void()> body() {
        return [this] { openVolume |= ui::drawSettingsPanel(state).openVolume; };
    }
    ImGuiID fieldId(const char* label, const char* item) {
        ImGuiID id = 0;
        frame([&] {
            ImGui::PushID(label);
            id = ImGui::GetID(item);
            ImGui::PopID();
        });
        return id;
    }
    // The browser's list of entries (a child window of the popup), or null while it is closed.
    static ImGuiWindow* entriesWindow() {
        for (ImGuiWindow* w : ImGui::GetCurrentContext()->Windows)
            if (w->Active && w->ParentWindow && std::string(w->ParentWindow->Name) == "Choose a file" &&
                std::string(w->Name).find("##entries") != std::string::npos)
                return w;
        return nullptr;
    }
    // Finds the entry `label` in the list by hovering down its middle; -1 when it is not there.
    float findEntry(const std::string& label) {
        ImGuiWindow* list = entriesWindow();
        if (!list) return -1.0f;
        const float x = list->Pos.x + 40.0f;
        return findItem(ImHashStr(label.c_str(), 0, list->ID), x, list->Pos.y, list->Pos.y + list->Size.y,
                        body());
    }
    float entryX() const { return entriesWindow()->Pos.x + 40.0f; }
};

} // namespace

TEST_F(FileBrowser, BrowseIntoAFolderAndDoubleClickAVolumeToOpenIt) {
    // A folder with a sub-folder holding a volume (neghip: its header and voxels) and a text file.
    const fs::path dir = testing_support::testOutputDir("file_browser") / "scans";
    fs::remove_all(dir);
    fs::create_directories(dir / "ct");
    for (const char* name : {"neghip.nhdr", "neghip_66x66x66_uint8.raw"})
        fs::copy_file(testing_support::assetDir() / "volumes" / name, dir / "ct" / name);
    std::ofstream(dir / "ct" / "notes.txt") << "not a volume";
    state.volumeFile = (dir / "old.nrrd").string(); // the browser opens in the field's folder

    // 1. Browse, beside the Volume field.
    const ImGuiID pathId = fieldId("Volume", "##path"), browseId = fieldId("Volume", "Browse");
    const float y = findItem(pathId, 30.0f, 0.0f, 300.0f, body());
    ASSERT_GE(y, 0.0f) << "no Volume field";
    const float x = findItemInRow(browseId, y, body());
    ASSERT_GE(x, 0.0f) << "no Browse button beside the Volume field";
    click(x, y, body());
    frame(body());
    ASSERT_NE(entriesWindow(), nullptr) << "Browse opened no browser";
    EXPECT_EQ(state.fileBrowser.listing.folder, fs::canonical(dir));

    // 2. Into ct/: the volume's header and voxels are listed, the text file is not.
    const float ctY = findEntry("ct/");
    ASSERT_GE(ctY, 0.0f) << "the folder ct/ is not listed";
    click(entryX(), ctY, body());
    frame(body());
    EXPECT_EQ(state.fileBrowser.listing.folder, fs::canonical(dir / "ct"));
    std::vector<std::string> listed;
    for (const ui::FolderEntry& e : state.fileBrowser.listing.entries)
        listed.push_back(e.name);
    EXPECT_THAT(listed, testing::ElementsAre("neghip.nhdr", "neghip_66x66x66_uint8.raw"));
    EXPECT_EQ(state.fileBrowser.listing.hiddenFiles, 1u);

    // 3. A double-click on the header: the field holds it, the panel opens it, the browser closes.
    const float volumeY = findEntry("neghip.nhdr");
    ASSERT_GE(volumeY, 0.0f) << "neghip.nhdr is not listed";
    const float volumeX = entryX();
    openVolume = false;
    click(volumeX, volumeY, body());
    EXPECT_FALSE(openVolume) << "a single click only picks the file";
    EXPECT_EQ(state.fileBrowser.name, "neghip.nhdr");
    click(volumeX, volumeY, body());
    EXPECT_TRUE(openVolume);
    EXPECT_EQ(fs::path(state.volumeFile), fs::canonical(dir / "ct") / "neghip.nhdr");
    frame(body());
    EXPECT_EQ(entriesWindow(), nullptr) << "the browser stays open after a file was chosen";
    EXPECT_EQ(renderer::loadVolume(state.volumeFile).dims, glm::ivec3(66)); // what the app then opens
}

TEST_F(FileBrowser, RecentFilesAreKeptInTheConfigFolderAndOfferedNextRun) {
    const fs::path config = testing_support::testOutputDir("file_browser") / "config";
    fs::remove_all(config);
    state.configDir = config;
    const fs::path volume = testing_support::assetDir() / "volumes" / "neghip.nhdr";
    ui::noteRecentFile(state, ui::FileKind::Volume, volume);
    ui::noteRecentFile(state, ui::FileKind::Session, "session.json");
    // The next run reads the same lists back.
    const ui::RecentFiles next = ui::loadRecentFiles(config);
    ASSERT_EQ(next.of(ui::FileKind::Volume).size(), 1u);
    EXPECT_EQ(fs::path(next.of(ui::FileKind::Volume)[0]), fs::absolute(volume).lexically_normal());
    EXPECT_EQ(fs::path(next.of(ui::FileKind::Session)[0]), fs::absolute("session.json"));
    // With no config folder (state.configDir empty) nothing is written.
    ui::EditorState scratch;
    ui::noteRecentFile(scratch, ui::FileKind::Volume, volume);
    EXPECT_EQ(scratch.recentFiles.of(ui::FileKind::Volume).size(), 1u);
}
