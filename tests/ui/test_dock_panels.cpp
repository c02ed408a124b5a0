// Panels in the dock layout: closed from the View menu, still closed after a restart (the layout kept in
// the config folder), back with Reset layout; moved to another dock from their tab's right-click menu.
// Driven through ImGui with synthetic input, as the editor draws them: a menu bar, then the dock space.
#include "imgui_null.h"
#include "renderer/errors.h"
#include "test_paths.h"
#include "ui/dock_layout.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <fstream>
#include <set>

namespace {

namespace fs = std::filesystem;

class DockPanels : public ImGuiNull {
  protected:
    ui::DockLayout layout = ui::makeEditorLayout();
    std::vector<ui::DockPanel> panels;
    std::set<std::string> drawn; // the panels whose contents were drawn in the last frame

    void SetUp() override {
        ImGuiNull::SetUp();
        for (const auto& [title, region] : std::vector<std::pair<std::string, std::string>>{
                 {"Settings", "left"}, {"Viewport", "viewport"}, {"Stats", "bottom"}, {"Help", "bottom"}})
            panels.push_back({title, region, [this, title] { drawn.insert(title); }});
    }

    void frame() {
        drawn.clear();
        ImGui::NewFrame();
        if (ImGui::BeginMainMenuBar()) {
            if (ImGui::BeginMenu("View")) {
                ui::drawViewMenuItems(layout, panels);
                ImGui::EndMenu();
            }
            ImGui::EndMainMenuBar();
        }
        ui::drawDockSpace(layout, panels);
        ImGui::Render();
    }
    void mouse(float x, float y, int button, bool down) {
        ImGui::GetIO().MousePos = ImVec2(x, y);
        ImGui::GetIO().MouseDown[button] = down;
    }
    void click(ImVec2 at, int button = 0) {
        mouse(at.x, at.y, button, true);
        frame();
        mouse(at.x, at.y, button, false);
        frame();
    }
    // Opens the View menu and clicks `item` in it.
    void clickViewMenu(const std::string& item) {
        ImGuiWindow* bar = ImGui::FindWindowByName("##MainMenuBar");
        ASSERT_NE(bar, nullptr);
        click({bar->Pos.x + 20.0f, bar->Pos.y + bar->Size.y * 0.5f}); // "View", the bar's first menu
        const ImGuiWindow* menu = ImGui::FindWindowByName("##Menu_00");
        ASSERT_TRUE(menu && menu->Active) << "the View menu did not open";
        const ImGuiID id = ImHashStr(item.c_str(), 0, menu->ID);
        for (float y = menu->Pos.y + 2.0f; y < menu->Pos.y + menu->Size.y; y += 3.0f) {
            mouse(menu->Pos.x + 20.0f, y, 0, false);
            frame();
            if (ImGui::GetCurrentContext()->HoveredId == id) {
                frame(); // a submenu passed on the way ("Move to") closes
                click({menu->Pos.x + 20.0f, y});
                return;
            }
        }
        FAIL() << "no " << item << " in the View menu";
    }
    // The tab of `title` in the leaf `region`'s tab bar.
    ImVec2 findTab(const std::string& region, const std::string& title) {
        frame();
        const ImGuiWindow* window = ImGui::FindWindowByName(("##dock_" + region).c_str());
        if (!window) return {-1, -1};
        const ImGuiID tabBar = ImHashStr("##tabs", 0, window->ID);
        const ImGuiID id = ImHashStr(title.c_str(), 0, tabBar);
        for (float x = window->Pos.x + 4.0f; x < window->Pos.x + window->Size.x; x += 4.0f) {
            mouse(x, window->Pos.y + 12.0f, 0, false);
            frame();
            if (ImGui::GetCurrentContext()->HoveredId == id) return {x, window->Pos.y + 12.0f};
        }
        return {-1, -1};
    }
    void restart(const fs::path& config) {
        ui::saveDockLayout(layout, config);
        ImGui::DestroyContext(); // a new run: a fresh ImGui and the default layout, then the kept one
        panels.clear();
        SetUp();
        layout = ui::makeEditorLayout();
        ui::loadDockLayout(layout, config);
        frame();
        frame();
    }
};

} // namespace

TEST_F(DockPanels, AClosedPanelStaysClosedAfterARestartAndResetLayoutBringsItBack) {
    const fs::path config = testing_support::testOutputDir("dock_panels") / "close";
    fs::remove_all(config);
    frame();
    frame();
    ASSERT_TRUE(drawn.contains("Stats")); // the bottom leaf's first tab, in front
    clickViewMenu("Stats");
    frame();
    EXPECT_FALSE(drawn.contains("Stats"));
    EXPECT_TRUE(drawn.contains("Help")) << "the leaf's other panel comes to the front";
    EXPECT_FALSE(ui::panelOpen(layout, panels[2]));

    restart(config);
    EXPECT_FALSE(ui::panelOpen(layout, panels[2])) << "the closed panel came back after a restart";
    EXPECT_FALSE(drawn.contains("Stats"));

    clickViewMenu("Reset layout");
    frame();
    EXPECT_TRUE(ui::panelOpen(layout, panels[2]));
    EXPECT_GE(findTab("bottom", "Stats").x, 0.0f) << "Reset layout did not bring the Stats tab back";
    EXPECT_EQ(layout.nodes[0].ratio, ui::makeEditorLayout().nodes[0].ratio);
}

TEST_F(DockPanels, APanelReopenedFromTheViewMenuComesToTheFront) {
    frame();
    frame();
    clickViewMenu("Stats"); // closes it: Help, beside it, is shown
    frame();
    ASSERT_TRUE(drawn.contains("Help"));
    clickViewMenu("Stats"); // opens it again, in front
    frame();
    EXPECT_TRUE(drawn.contains("Stats"));
    EXPECT_FALSE(drawn.contains("Help"));
}

TEST_F(DockPanels, APanelMovedToAnotherDockFromItsTabIsThereAfterARestart) {
    const fs::path config = testing_support::testOutputDir("dock_panels") / "move";
    fs::remove_all(config);
    frame();
    frame();
    const ImVec2 tab = findTab("bottom", "Help");
    ASSERT_GE(tab.x, 0.0f) << "no Help tab in the bottom dock";
    click(tab, 1); // right-click: the tab's menu
    ImGuiWindow* menu = nullptr;
    for (ImGuiWindow* w : ImGui::GetCurrentContext()->Windows)
        if (w->Active && (w->Flags & ImGuiWindowFlags_Popup)) menu = w;
    ASSERT_NE(menu, nullptr) << "right-clicking the tab opened no menu";
    const ImGuiID moveLeft = ImHashStr("Move to left", 0, menu->ID);
    bool moved = false;
    for (float y = menu->Pos.y + 2.0f; y < menu->Pos.y + menu->Size.y && !moved; y += 3.0f) {
        mouse(menu->Pos.x + 20.0f, y, 0, false);
        frame();
        if (ImGui::GetCurrentContext()->HoveredId == moveLeft) click({menu->Pos.x + 20.0f, y}), moved = true;
    }
    ASSERT_TRUE(moved) << "no 'Move to left' in the tab's menu";
    EXPECT_EQ(ui::panelRegion(layout, panels[3]), "left");
    EXPECT_GE(findTab("left", "Help").x, 0.0f) << "the Help tab is not in the left dock";

    restart(config);
    EXPECT_EQ(ui::panelRegion(layout, panels[3]), "left");
    EXPECT_GE(findTab("left", "Help").x, 0.0f);
    EXPECT_LT(findTab("bottom", "Help").x, 0.0f);
}

TEST(DockLayoutFile, SplitSizesRoundTripAndABadFileIsNamedAndChangesNothing) {
    const fs::path config = testing_support::testOutputDir("dock_panels") / "file";
    fs::remove_all(config);
    ui::DockLayout layout = ui::makeEditorLayout();
    ui::loadDockLayout(layout, config); // no file yet: the defaults
    EXPECT_EQ(layout.nodes[0].ratio, 0.25f);
    layout.nodes[0].ratio = 0.4f;
    layout.nodes[layout.find("centre")].ratio = 0.5f;
    ui::saveDockLayout(layout, config);
    ui::DockLayout next = ui::makeEditorLayout();
    ui::loadDockLayout(next, config);
    EXPECT_EQ(next.nodes[0].ratio, 0.4f);
    EXPECT_EQ(next.nodes[next.find("centre")].ratio, 0.5f);

    std::ofstream(config / "layout.json") << R"({"ratios": {"root": 1.5}})";
    ui::DockLayout kept = ui::makeEditorLayout();
    try {
        ui::loadDockLayout(kept, config);
        ADD_FAILURE() << "a ratio of 1.5 must be refused";
    } catch (const renderer::LoadError& e) {
        EXPECT_THAT(e.what(), testing::HasSubstr("layout.json"));
        EXPECT_THAT(e.what(), testing::HasSubstr("ratios.root"));
    }
    EXPECT_EQ(kept.nodes[0].ratio, 0.25f);
}
