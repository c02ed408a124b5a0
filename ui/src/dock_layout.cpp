// Split-tree layout math and its ImGui drawing. Owns only ratios and sizes; panels draw themselves.
#include "ui/dock_layout.h"

#include <imgui.h>
#include <imgui_internal.h> // ImGuiViewportP::GetBuildWorkRect

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace ui {

int DockLayout::find(const std::string& name) const {
    for (size_t i = 0; i < nodes.size(); ++i)
        if (nodes[i].name == name) return int(i);
    return -1;
}

DockLayout makeEditorLayout() {
    DockLayout layout;
    layout.nodes.resize(5);
    layout.nodes[0] = {.name = "root",
                       .first = 1,
                       .second = 2,
                       .axis = SplitAxis::Columns,
                       .ratio = 0.25f,
                       .minFirstPx = 220.0f,
                       .minSecondPx = 320.0f};
    layout.nodes[1] = {.name = "left"};
    layout.nodes[2] = {.name = "centre",
                       .first = 3,
                       .second = 4,
                       .axis = SplitAxis::Rows,
                       .ratio = 0.66f,
                       .minFirstPx = 160.0f,
                       .minSecondPx = 90.0f};
    layout.nodes[3] = {.name = "viewport", .fill = true};
    layout.nodes[4] = {.name = "bottom"};
    return layout;
}

float firstExtentPx(const DockNode& split, float availPx) {
    if (availPx <= 0.0f) return 0.0f;
    const float minSum = split.minFirstPx + split.minSecondPx;
    if (minSum > availPx) return std::floor(availPx * split.minFirstPx / minSum);
    return std::clamp(std::round(split.ratio * availPx), split.minFirstPx, availPx - split.minSecondPx);
}

void setFirstExtentPx(DockNode& split, float firstPx, float availPx) {
    if (availPx <= 0.0f) return;
    const float lo = std::min(split.minFirstPx, availPx);
    const float hi = std::max(lo, availPx - split.minSecondPx);
    split.ratio = std::clamp(firstPx, lo, hi) / availPx;
}

namespace {

void layoutNode(const DockLayout& layout, int index, Rect area, DockRects& out) {
    assert(index >= 0 && size_t(index) < layout.nodes.size() && "a split names a child that does not exist");
    out.node[index] = area;
    const DockNode& node = layout.nodes[index];
    if (node.isLeaf()) return;

    // The splitter may not be wider than the split itself (a window smaller than one bar).
    const bool columns = node.axis == SplitAxis::Columns;
    const float extent = columns ? area.w : area.h;
    const float bar = std::min(layout.splitterPx, extent);
    const float first = firstExtentPx(node, extent - bar);
    const float second = extent - bar - first;
    Rect a = area, s = area, b = area;
    if (columns) {
        a.w = first;
        s.x = area.x + first, s.w = bar;
        b.x = s.x + bar, b.w = second;
    } else {
        a.h = first;
        s.y = area.y + first, s.h = bar;
        b.y = s.y + bar, b.h = second;
    }
    out.splitter[index] = s;
    layoutNode(layout, node.first, a, out);
    layoutNode(layout, node.second, b, out);
}

ImVec2 topLeft(const Rect& r) { return {r.x, r.y}; }
ImVec2 size(const Rect& r) { return {r.w, r.h}; }

// One splitter bar: an invisible button over the bar; dragging it moves the split, measured from where
// the drag began so that a drag past a min size and back does not drift.
void drawSplitter(DockLayout& layout, int index, const Rect& area, const Rect& bar) {
    if (bar.w <= 0.0f || bar.h <= 0.0f) return;
    DockNode& node = layout.nodes[index];
    const bool columns = node.axis == SplitAxis::Columns;
    const float availPx = (columns ? area.w : area.h) - (columns ? bar.w : bar.h);

    ImGui::SetCursorScreenPos(topLeft(bar));
    ImGui::PushID(index);
    ImGui::InvisibleButton("##splitter", size(bar));
    ImGui::PopID();
    const bool hovered = ImGui::IsItemHovered(), active = ImGui::IsItemActive();
    if (ImGui::IsItemActivated()) layout.dragStartPx = firstExtentPx(node, availPx);
    if (active) {
        const ImVec2 drag = ImGui::GetMouseDragDelta(ImGuiMouseButton_Left, 0.0f);
        setFirstExtentPx(node, layout.dragStartPx + (columns ? drag.x : drag.y), availPx);
    }
    if (hovered || active)
        ImGui::SetMouseCursor(columns ? ImGuiMouseCursor_ResizeEW : ImGuiMouseCursor_ResizeNS);
    const ImU32 colour = ImGui::GetColorU32(active    ? ImGuiCol_SeparatorActive
                                            : hovered ? ImGuiCol_SeparatorHovered
                                                      : ImGuiCol_Separator);
    // Idle bars draw a 1 px line in their middle; hovered or dragged ones light up whole.
    ImVec2 lo = topLeft(bar), hi{bar.right(), bar.bottom()};
    if (!hovered && !active) {
        if (columns)
            lo.x = hi.x = std::floor(bar.x + bar.w * 0.5f), hi.x += 1.0f;
        else
            lo.y = hi.y = std::floor(bar.y + bar.h * 0.5f), hi.y += 1.0f;
    }
    ImGui::GetWindowDrawList()->AddRectFilled(lo, hi, colour);
}

// The right-click menu on a panel's tab: move it to another leaf, or close it.
void drawTabMenu(DockLayout& layout, const DockPanel& panel) {
    if (!ImGui::BeginPopupContextItem()) return;
    const std::string here = panelRegion(layout, panel);
    for (const std::string& region : panelRegions(layout))
        if (region != here && ImGui::MenuItem(("Move to " + region).c_str()))
            movePanel(layout, panel, region);
    if (ImGui::MenuItem("Close")) setPanelOpen(layout, panel, false);
    ImGui::EndPopup();
}

} // namespace

bool panelMovable(const DockLayout& layout, const DockPanel& panel) {
    const int node = layout.find(panel.region);
    return node < 0 || !layout.nodes[size_t(node)].fill;
}

std::string panelRegion(const DockLayout& layout, const DockPanel& panel) {
    const auto it = layout.panels.find(panel.title);
    if (it == layout.panels.end() || !panelMovable(layout, panel)) return panel.region;
    const int node = layout.find(it->second.region);
    return node >= 0 && layout.nodes[size_t(node)].isLeaf() ? it->second.region : panel.region;
}

bool panelOpen(const DockLayout& layout, const DockPanel& panel) {
    const auto it = layout.panels.find(panel.title);
    return !panelMovable(layout, panel) || it == layout.panels.end() || it->second.open;
}

void setPanelOpen(DockLayout& layout, const DockPanel& panel, bool open) {
    if (!panelMovable(layout, panel) || panelOpen(layout, panel) == open) return;
    layout.panels[panel.title] = {panelRegion(layout, panel), open};
    if (open) layout.toFront.push_back(panel.title); // reopened: shown, not behind another tab
}

void movePanel(DockLayout& layout, const DockPanel& panel, const std::string& region) {
    if (!panelMovable(layout, panel)) return;
    layout.panels[panel.title] = {region, true};
    layout.toFront.push_back(panel.title);
}

std::vector<std::string> panelRegions(const DockLayout& layout) {
    std::vector<std::string> regions;
    for (const DockNode& node : layout.nodes)
        if (node.isLeaf() && !node.fill) regions.push_back(node.name);
    return regions;
}

void drawViewMenuItems(DockLayout& layout, const std::vector<DockPanel>& panels) {
    for (const DockPanel& panel : panels) {
        if (!panelMovable(layout, panel)) continue;
        const bool open = panelOpen(layout, panel);
        if (ImGui::MenuItem(panel.title.c_str(), nullptr, open)) setPanelOpen(layout, panel, !open);
    }
    ImGui::Separator();
    if (ImGui::BeginMenu("Move to")) {
        for (const DockPanel& panel : panels) {
            if (!panelMovable(layout, panel) || !ImGui::BeginMenu(panel.title.c_str())) continue;
            const std::string here = panelRegion(layout, panel);
            for (const std::string& region : panelRegions(layout))
                if (ImGui::MenuItem(region.c_str(), nullptr, region == here) && region != here)
                    movePanel(layout, panel, region);
            ImGui::EndMenu();
        }
        ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Reset layout")) layout = makeEditorLayout();
}

DockRects computeDockRects(const DockLayout& layout, Rect window) {
    DockRects rects;
    rects.node.resize(layout.nodes.size());
    rects.splitter.resize(layout.nodes.size());
    if (!layout.nodes.empty()) layoutNode(layout, 0, window, rects);
    return rects;
}

void drawDockSpace(DockLayout& layout, const std::vector<DockPanel>& panels, const std::vector<std::string>& select) {
    // What a menu bar drawn earlier this frame leaves: WorkPos/WorkSize learn of it a frame late, and a
    // first frame at another size would frame the first view for another aspect.
    const ImRect work = static_cast<ImGuiViewportP*>(ImGui::GetMainViewport())->GetBuildWorkRect();
    const Rect window{work.Min.x, work.Min.y, work.GetWidth(), work.GetHeight()};
    const DockRects rects = computeDockRects(layout, window);
    constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                        ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoBringToFrontOnFocus |
                                        ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoSavedSettings;

    const std::vector<std::string> toFront = std::exchange(layout.toFront, {});
    ImGui::PushStyleVar(ImGuiStyleVar_WindowRounding, 0.0f); // docked windows are square (all of them)
    // 1. One window per leaf with a tab bar of the panels docked there.
    for (size_t i = 0; i < layout.nodes.size(); ++i) {
        const DockNode& leaf = layout.nodes[i];
        if (!leaf.isLeaf()) continue;
        ImGui::SetNextWindowPos(topLeft(rects.node[i]));
        ImGui::SetNextWindowSize(size(rects.node[i]));
        ImGuiWindowFlags flags = kFixed;
        if (leaf.fill) {
            flags |= ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse;
            ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
        }
        ImGui::Begin(("##dock_" + leaf.name).c_str(), nullptr, flags);
        if (leaf.fill) ImGui::PopStyleVar();
        bool any = false;
        if (ImGui::BeginTabBar("##tabs")) {
            for (const DockPanel& panel : panels) {
                const bool front = std::ranges::find(select, panel.title) != select.end() ||
                                   std::ranges::find(toFront, panel.title) != toFront.end();
                if (front) setPanelOpen(layout, panel, true);
                if (panelRegion(layout, panel) != leaf.name || !panelOpen(layout, panel)) continue;
                any = true;
                const bool movable = panelMovable(layout, panel);
                bool open = true;
                const bool shown = ImGui::BeginTabItem(panel.title.c_str(), movable ? &open : nullptr,
                                                       front ? ImGuiTabItemFlags_SetSelected : 0);
                if (movable) drawTabMenu(layout, panel);
                if (shown) {
                    panel.draw();
                    ImGui::EndTabItem();
                }
                if (!open) setPanelOpen(layout, panel, false);
            }
            ImGui::EndTabBar();
        }
        if (!any) ImGui::TextDisabled("Closed panels open again from the View menu");
        ImGui::End();
    }
    // 2. Host window covering the whole window behind the leaves: it owns the splitter bars. ImGui puts
    //    a new NoBringToFrontOnFocus window at the back of the stack, so the host, created after the
    //    leaves, stays behind them: the leaves get the mouse, the host only gets the gaps.
    ImGui::SetNextWindowPos(topLeft(window));
    ImGui::SetNextWindowSize(size(window));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.0f);
    ImGui::Begin("##dock_host", nullptr,
                 kFixed | ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse |
                     ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoFocusOnAppearing);
    ImGui::PopStyleVar(2);
    for (size_t i = 0; i < layout.nodes.size(); ++i)
        if (!layout.nodes[i].isLeaf()) drawSplitter(layout, int(i), rects.node[i], rects.splitter[i]);
    ImGui::End();

    ImGui::PopStyleVar();
}

} // namespace ui
