#include "ui/text_wrap.h"

namespace ui {

namespace {

// Appends the lines of one paragraph (no newline in it): greedy, a word at a time.
void wrapParagraph(std::string_view text, float width, const std::function<float(std::string_view)>& measure,
                   std::vector<std::string_view>& lines) {
    size_t start = 0;
    do {
        size_t end = std::string_view::npos;   // the longest fitting end found so far, at a word's end
        for (size_t pos = start;;) {
            const size_t space = text.find(' ', pos);
            const size_t wordEnd = space == std::string_view::npos ? text.size() : space;
            if (end != std::string_view::npos && measure(text.substr(start, wordEnd - start)) > width) break;
            end = wordEnd;
            if (space == std::string_view::npos) break;
            pos = space + 1;
        }
        lines.push_back(text.substr(start, end - start));
        start = text.find_first_not_of(' ', end);
    } while (start != std::string_view::npos);
}

} // namespace

std::vector<std::string_view> wrapAtSpaces(std::string_view text, float width,
                                           const std::function<float(std::string_view)>& measure) {
    std::vector<std::string_view> lines;
    for (size_t start = 0;;) {
        const size_t newline = text.find('\n', start);
        wrapParagraph(text.substr(start, newline == std::string_view::npos ? std::string_view::npos : newline - start),
                      width, measure, lines);
        if (newline == std::string_view::npos) return lines;
        start = newline + 1;
    }
}

} // namespace ui
