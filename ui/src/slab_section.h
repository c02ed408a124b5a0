// Settings > Image-aligned slabs, for panels.cpp (slab_section.cpp).
#pragma once
#include "ui/editor_state.h"

namespace ui {

// On/off, thickness and classification of the slab frame a still view ends in, with the app's status of
// it; greyed where the view cannot have one. Returns whether anything changed (a new view to render).
bool drawSlabSection(EditorState& state);

} // namespace ui
