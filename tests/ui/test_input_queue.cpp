// The input queue: however many events fall between two UI frames, each button or key change gets a
// frame of its own with the pointer where it happened, and nothing typed is lost or reordered.
#include "ui/input_queue.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using ui::InputEvent;
using Kind = InputEvent::Kind;

namespace {

InputEvent move(double x, double y) { return {.kind = Kind::MouseMove, .x = x, .y = y}; }
InputEvent button(bool down) { return {.kind = Kind::MouseButton, .code = 0, .down = down}; }
InputEvent key(int code, bool down) { return {.kind = Kind::Key, .code = code, .down = down}; }
InputEvent character(char c) { return {.kind = Kind::Char, .code = c}; }

} // namespace

// A whole drag inside one slow frame: press at (10, 10), move to (200, 50), release there, then the
// pointer moves on to (400, 300). ImGui must see the press at (10, 10), the pointer at (200, 50) with the
// button still down, and the release at (200, 50); the move after the release only after it.
TEST(InputQueue, ADragWithinOneFrameEndsWhereTheButtonWasReleased) {
    ui::InputQueue q;
    for (const InputEvent& e : {move(10, 10), button(true), move(100, 30), move(200, 50), button(false), move(400, 300)})
        q.push(e);
    ui::FrameInput f = q.takeFrame(); // the pointer before the press
    EXPECT_FALSE(f.buttons[0]);
    EXPECT_EQ(f.mouseX, 10.0);
    f = q.takeFrame(); // the press, alone
    EXPECT_TRUE(f.buttons[0]);
    EXPECT_EQ(f.mouseX, 10.0);
    EXPECT_EQ(f.mouseY, 10.0);
    f = q.takeFrame(); // the drag's moves, button down
    EXPECT_TRUE(f.buttons[0]);
    EXPECT_EQ(f.mouseX, 200.0);
    EXPECT_EQ(f.mouseY, 50.0);
    f = q.takeFrame(); // the release where it happened
    EXPECT_FALSE(f.buttons[0]);
    EXPECT_EQ(f.mouseX, 200.0);
    EXPECT_EQ(f.mouseY, 50.0);
    f = q.takeFrame(); // and only then the move after it
    EXPECT_EQ(f.mouseX, 400.0);
    EXPECT_TRUE(q.empty());
}

// Ctrl+A then a typed path, all between two frames, in the two orders X servers deliver (xdotool
// releases Ctrl before A): some frame has Ctrl and A down together, and the characters come after it.
TEST(InputQueue, AShortcutAndTypingBetweenTwoFramesAreAllSeenInOrder) {
    constexpr int kCtrl = 341, kA = 65;
    for (bool ctrlFirst : {false, true}) {
        SCOPED_TRACE(ctrlFirst ? "Ctrl released first" : "A released first");
        ui::InputQueue q;
        q.push(key(kCtrl, true));
        q.push(key(kA, true));
        q.push(key(ctrlFirst ? kCtrl : kA, false));
        q.push(key(ctrlFirst ? kA : kCtrl, false));
        for (char c : {'o', 'u', 't'}) q.push(character(c));
        std::string typed;
        bool shortcut = false;
        while (!q.empty()) {
            const ui::FrameInput f = q.takeFrame();
            if (f.keys[kCtrl] && f.keys[kA]) {
                shortcut = true;
                EXPECT_TRUE(typed.empty()) << "characters before the shortcut";
            }
            for (unsigned c : f.chars) typed += char(c);
        }
        EXPECT_TRUE(shortcut) << "Ctrl+A never seen";
        EXPECT_EQ(typed, "out");
    }
}

// Typing "ab", Backspace, "c" between two frames: ImGui takes a frame's characters before its keys, so
// the Backspace waits for the frame after "ab" and "c" for the one after it: "ac", as typed.
TEST(InputQueue, ABackspaceAfterTypedCharactersWaitsForTheirFrame) {
    constexpr int kBackspace = 259, kA = 65, kB = 66, kC = 67;
    ui::InputQueue q;
    for (const InputEvent& e : {key(kA, true), character('a'), key(kA, false), key(kB, true), character('b'),
                                key(kB, false), key(kBackspace, true), key(kBackspace, false), key(kC, true),
                                character('c'), key(kC, false)})
        q.push(e);
    std::string text;
    int frames = 0;
    while (!q.empty()) {
        const ui::FrameInput f = q.takeFrame();
        ++frames;
        for (unsigned c : f.chars) text += char(c); // ImGui: characters first...
        if (f.keys[kBackspace] && !text.empty()) text.pop_back(); // ...then keys
    }
    EXPECT_EQ(text, "ac");
    EXPECT_LE(frames, 8); // at most a frame per key change
}

// A repeat (press while pressed) changes nothing and does not cost a frame; the state persists between
// frames with nothing queued.
TEST(InputQueue, StatesPersistAndRepeatsTakeNoFrame) {
    ui::InputQueue q;
    q.push(button(true));
    q.push(button(true));
    q.push(move(5, 6));
    ui::FrameInput f = q.takeFrame();
    EXPECT_TRUE(f.buttons[0]);
    f = q.takeFrame();
    EXPECT_TRUE(f.buttons[0]);
    EXPECT_EQ(f.mouseX, 5.0);
    EXPECT_TRUE(q.empty());
    f = q.takeFrame();
    EXPECT_TRUE(f.buttons[0]);
    EXPECT_EQ(f.mouseY, 6.0);
}
