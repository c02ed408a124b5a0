// wrapAtSpaces: panel text breaks between words only, never inside a number.
#include "ui/text_wrap.h"

#include <gtest/gtest.h>

#include <string>

namespace {

const auto kOnePerChar = [](std::string_view s) { return float(s.size()); };

std::string joined(const std::vector<std::string_view>& lines) {
    std::string out;
    for (std::string_view line : lines) out += (out.empty() ? "" : " ") + std::string(line);
    return out;
}

TEST(TextWrap, BreaksAtSpacesSoNumbersStayWhole) {
    const std::string text = "A kernel of sigma 1.05 covers sigma x f / depth pixels: reconstruction only above 3.33 px";
    const auto lines = ui::wrapAtSpaces(text, 30.0f, kOnePerChar);
    ASSERT_GT(lines.size(), 2u);
    for (std::string_view line : lines) {
        EXPECT_LE(line.size(), 30u) << line;
        EXPECT_NE(line.front(), ' ') << line;
        EXPECT_NE(line.back(), ' ') << line;
    }
    EXPECT_EQ(joined(lines), text);   // nothing lost, and "3.33" and "1.05" each on one line
    // Greedy: no line could have taken the next line's first word.
    for (size_t i = 0; i + 1 < lines.size(); ++i) {
        const std::string_view next = lines[i + 1].substr(0, lines[i + 1].find(' '));
        EXPECT_GT(lines[i].size() + 1 + next.size(), 30u) << lines[i];
    }
}

TEST(TextWrap, AWordWiderThanTheRegionKeepsALineOfItsOwn) {
    const auto lines = ui::wrapAtSpaces("a 0.000123456789012 b", 5.0f, kOnePerChar);
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0], "a");
    EXPECT_EQ(lines[1], "0.000123456789012");
    EXPECT_EQ(lines[2], "b");
}

TEST(TextWrap, NewlinesAlwaysBreakAndShortTextIsOneLine) {
    const auto lines = ui::wrapAtSpaces("one two\nthree", 100.0f, kOnePerChar);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0], "one two");
    EXPECT_EQ(lines[1], "three");
    EXPECT_EQ(ui::wrapAtSpaces("", 10.0f, kOnePerChar), std::vector<std::string_view>{""});
    EXPECT_EQ(ui::wrapAtSpaces("x", 0.0f, kOnePerChar), std::vector<std::string_view>{"x"});
}

} // namespace
