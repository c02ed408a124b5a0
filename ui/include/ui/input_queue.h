// Input events in the order they happened, handed to ImGui a frame's worth at a time. Dear ImGui 1.86
// reads the mouse and keys as states once a frame, so a press, a move and a release that fall in one
// frame collapse: a drag ends where the pointer went after the release, a key pressed and released
// between two frames (Ctrl+A) is never seen. The queue "trickles" instead: a frame ends before an event
// that would hide an earlier one from ImGui (a button's or key's change after a move or another change, a
// move after a button's change, a key's change after typed characters), which then starts the next frame. No ImGui or GLFW here: the editor's window feeds it and applies its states.
#pragma once
#include <array>
#include <cstdint>
#include <deque>
#include <vector>

namespace ui {

struct InputEvent {
    enum class Kind { MouseMove, MouseButton, Key, Char, Scroll } kind = Kind::MouseMove;
    double x = 0.0, y = 0.0; // MouseMove: position (screen coordinates); Scroll: offsets
    int code = 0;            // MouseButton: button; Key: key code; Char: code point
    bool down = false;       // MouseButton, Key: pressed (true) or released
};

// What ImGui sees in one frame.
struct FrameInput {
    static constexpr int kButtons = 5;
    static constexpr int kKeys = 512;
    bool hasMouse = false; // a MouseMove was ever seen (else the pointer is unknown)
    double mouseX = 0.0, mouseY = 0.0;
    std::array<bool, kButtons> buttons{};
    std::array<bool, kKeys> keys{};
    std::vector<unsigned> chars; // typed this frame, in order
    double scrollX = 0.0, scrollY = 0.0;
};

class InputQueue {
  public:
    void push(const InputEvent& event) { m_events.push_back(event); }
    bool empty() const { return m_events.empty(); }
    // The next frame's input: the state after the events this frame takes (see above); they leave the
    // queue, the rest wait for the next frames.
    FrameInput takeFrame();

  private:
    std::deque<InputEvent> m_events;
    FrameInput m_state; // buttons, keys and pointer persist from frame to frame
};

} // namespace ui
