// The filter regimes' names and colours, shared by the Filters panel and the viewport's heatmap legend.
#pragma once
#include <imgui.h>

namespace ui {

// Indexed by renderer::FilterMode (0 reconstruction, 1 low-pass, 2 EWA).
inline const char* const kModeName[3] = {"reconstruction", "low-pass", "EWA"};
// The heatmap's own colours: the renderer writes pure red, green and blue (one-hot per filter).
inline const ImU32 kHeatmapColour[3] = {IM_COL32(255, 0, 0, 255), IM_COL32(0, 255, 0, 255),
                                        IM_COL32(0, 0, 255, 255)};
// The same hues lightened, for text on ImGui's dark background (pure blue text is hard to read).
inline const ImVec4 kModeColour[3] = {ImVec4(1.0f, 0.3f, 0.3f, 1.0f), ImVec4(0.3f, 1.0f, 0.3f, 1.0f),
                                      ImVec4(0.4f, 0.5f, 1.0f, 1.0f)};

} // namespace ui
