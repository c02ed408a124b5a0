// The editor's docked layout, built by hand because Debian's ImGui 1.86 has no docking branch: a
// small tree of splits whose leaves are regions hosting tabbed panels. The rectangle math is pure (tests
// check it with no GL and no ImGui context); drawDockSpace() is the only part that talks to ImGui.
#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace ui {

struct Rect {
    float x = 0, y = 0, w = 0, h = 0; // display pixels, origin top-left, y down (ImGui's convention)
    float right() const { return x + w; }
    float bottom() const { return y + h; }
};

enum class SplitAxis {
    Columns, // first child left of the splitter bar, second right of it
    Rows,    // first child above the splitter bar, second below it
};

struct DockNode {
    std::string name;            // a leaf's region name; panels name it in DockPanel::region
    int first = -1, second = -1; // child node indices; a leaf has first == -1
    SplitAxis axis = SplitAxis::Columns;
    float ratio = 0.5f;         // first child's share of the extent left after the splitter bar
    float minFirstPx = 100.0f;  // smallest extent along the axis each child gets while the
    float minSecondPx = 100.0f; // split is at least minFirstPx + minSecondPx wide
    bool fill = false;          // leaf: no padding or scrolling, the panel fills it (viewport)

    bool isLeaf() const { return first < 0; }
};

// Where the user put a panel, when it differs from its DockPanel defaults (docked in `region`, open).
struct PanelPlacement {
    std::string region; // a leaf's name; one the layout lacks falls back to the panel's default
    bool open = true;   // closed: no tab; the View menu opens it again
};

struct DockLayout {
    std::vector<DockNode> nodes; // nodes[0] is the root
    float splitterPx = 6.0f;     // thickness of every splitter bar
    float dragStartPx = 0.0f;    // first child's extent when the active splitter drag began
    std::map<std::string, PanelPlacement> panels; // by panel title; absent: the panel's defaults
    std::vector<std::string> toFront; // panels to bring to the front of their leaves next frame (not kept)

    int find(const std::string& name) const; // index of the node called `name`; -1 when absent
};

// The editor's tree: left column | (centre viewport over bottom strip). Regions: "left", "viewport",
// "bottom". Ratios 0.25 and 0.66 (at 1280x800 the bottom strip is 270 px: the Filters panel with
// Measure's table and the Performance chart show whole); min sizes left 220, viewport 320 x 160, bottom 90.
DockLayout makeEditorLayout();

struct DockRects {
    std::vector<Rect> node;     // per node: the area it covers (leaves tile the window)
    std::vector<Rect> splitter; // per node: its splitter bar; zero-sized for leaves
};

// Tiles `window` with the leaves and splitter bars: no gaps, no overlaps, whole pixels when the
// window is in whole pixels. Ratios are read, never written, so a window that shrinks below the min
// sizes and grows back returns to the same layout.
DockRects computeDockRects(const DockLayout& layout, Rect window);

// First child's extent of a split whose children share `availPx` (splitter excluded): ratio * availPx
// rounded and clamped to the min sizes; when both mins do not fit, the extent is shared in proportion
// to them (mins 200 and 100 in 150 px -> 100 and 50).
float firstExtentPx(const DockNode& split, float availPx);
// Sets the ratio so the first child gets `firstPx`, clamped to the min sizes: a drag stops at them.
void setFirstExtentPx(DockNode& split, float firstPx, float availPx);

struct DockPanel {
    std::string title;          // tab label, unique across panels
    std::string region;         // name of the leaf it is docked in by default
    std::function<void()> draw; // draws the contents inside the tab
};

// Whether the user may close `panel` or move it: not when its leaf is one it fills (the viewport).
bool panelMovable(const DockLayout& layout, const DockPanel& panel);

// Where `panel` is docked and whether it is open in `layout` (its placement, else its defaults).
std::string panelRegion(const DockLayout& layout, const DockPanel& panel);
bool panelOpen(const DockLayout& layout, const DockPanel& panel);
// Closes or reopens `panel`, or docks it in the leaf `region` (opening it); fixed panels stay put.
void setPanelOpen(DockLayout& layout, const DockPanel& panel, bool open);
void movePanel(DockLayout& layout, const DockPanel& panel, const std::string& region);
// The leaves a panel can be moved to: every leaf but those a panel fills (the viewport's).
std::vector<std::string> panelRegions(const DockLayout& layout);

// The View menu's items, for a menu bar's "View" menu: a check per panel (close / reopen), "Move to"
// per panel, and "Reset layout" (makeEditorLayout's splits, every panel back in place and open).
void drawViewMenuItems(DockLayout& layout, const std::vector<DockPanel>& panels);

// The layout between runs: the split ratios (by node name) and the panels' placements, as layout.json in
// `folder`, written atomically. Loading applies the file onto `layout` (one from makeEditorLayout); splits
// or panels it does not know are ignored. A missing file changes nothing; a file that is not what
// saveDockLayout writes throws LoadError naming it and the field, and leaves `layout` unchanged.
void saveDockLayout(const DockLayout& layout, const std::filesystem::path& folder);
void loadDockLayout(DockLayout& layout, const std::filesystem::path& folder);

// Fills ImGui's main viewport: splitter bars (drags edit the layout's ratios) in a host window behind,
// then one fixed, undecorated window per leaf with a tab bar of that leaf's open panels. A tab's close
// button closes its panel; right-clicking a tab offers "Move to" the other leaves. The panels titled in
// `select` are opened and brought to the front of their leaves. Call between ImGui::NewFrame() and
// ImGui::Render().
void drawDockSpace(DockLayout& layout, const std::vector<DockPanel>& panels,
                   const std::vector<std::string>& select = {});

} // namespace ui
