// The short confirmation after a save: "Saved my_ct.json" in the window's corner for a few seconds,
// then fading out. Failures do not go here: they keep the error modal (state.errorMessage), which
// names the file and stays until dismissed.
#pragma once
#include <filesystem>
#include <string>

namespace ui {

struct SaveNotice {
    static constexpr double kShownS = 3.0; // fully visible this long ...
    static constexpr double kFadeS = 1.0;  // ... then fading out over this
    std::string text;                      // "Saved view.png (1280 x 720)"; empty: none
    std::string folder;                    // where the file went, in smaller print
    double shownAtS = -1.0;                // the UI clock when first drawn; -1: not drawn yet
};

// The notice for `file` just written; `detail` (e.g. the image size) follows the name in brackets.
SaveNotice savedNotice(const std::filesystem::path& file, const std::string& detail = {});

// The notice's opacity `sinceS` seconds after it was first drawn: 1, then down to 0 over kFadeS.
float saveNoticeAlpha(double sinceS);

// Draws `notice` at the bottom right of the main viewport (over whatever is there, taking no input)
// while it has not faded out; clears it once it has. Call between NewFrame and Render.
void drawSaveNotice(SaveNotice& notice);

} // namespace ui
