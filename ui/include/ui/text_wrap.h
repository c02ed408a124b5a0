// Line breaks for panel text. ImGui's TextWrapped also breaks after '.' and ',', which splits a number
// such as 3.33 over two lines; these break at spaces (and newlines) only.
#pragma once
#include <functional>
#include <string_view>
#include <vector>

namespace ui {

// `text` cut into lines at spaces, each as long as `measure` finds fits in `width`; a word wider than that
// keeps a line of its own. The spaces at a break are dropped; a newline always breaks.
std::vector<std::string_view> wrapAtSpaces(std::string_view text, float width,
                                           const std::function<float(std::string_view)>& measure);

} // namespace ui
