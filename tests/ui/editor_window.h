// Where the editor's panels are in the 1280x800 window the editor tests open: the dock space lies below
// the View menu bar, one ImGui frame high (the default font at 13 px plus padding).
#pragma once
#include "ui/dock_layout.h"

namespace testing_support {

constexpr float kMenuBarPx = 19.0f;
inline const ui::Rect kEditorDockArea{0, kMenuBarPx, 1280, 800 - kMenuBarPx};

} // namespace testing_support
