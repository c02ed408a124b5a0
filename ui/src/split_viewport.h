// The split view's drawing, for panels.cpp (split_viewport.cpp): its controls and its panes.
#pragma once
#include "ui/panels.h"

namespace ui {

// Settings > Split view: on/off, each pane's filter and compositing, the difference pane. Turned on, both
// panes take `viewCompositing`. Returns whether anything changed (a new view to render).
bool drawSplitViewSection(EditorState& state, renderer::Compositing viewCompositing);

// overlay.panes side by side over the rectangle at (x, y), w x h screen pixels (splitPaneRects), each with
// its label; the difference pane with its figures and colour scale.
void drawSplitPanes(const ViewportOverlay& overlay, float x, float y, float w, float h);

} // namespace ui
