// InputQueue::takeFrame (input_queue.h): the events in order, a frame ending where the next would hide one.
#include "ui/input_queue.h"

#include <bitset>
#include <cstddef>

namespace ui {

FrameInput InputQueue::takeFrame() {
    m_state.chars.clear();
    m_state.scrollX = m_state.scrollY = 0.0;
    // What this frame took so far: an event that would hide one of these from ImGui waits for the next.
    bool moved = false, typed = false, buttonChanged = false;
    std::bitset<FrameInput::kKeys> keysChanged;
    for (; !m_events.empty(); m_events.pop_front()) {
        const InputEvent& e = m_events.front();
        if (e.kind == InputEvent::Kind::MouseMove) {
            if (buttonChanged) break; // the press or release is seen where it happened
            m_state.hasMouse = true;
            m_state.mouseX = e.x, m_state.mouseY = e.y;
            moved = true;
        } else if (e.kind == InputEvent::Kind::MouseButton && e.code >= 0 && e.code < FrameInput::kButtons) {
            bool& down = m_state.buttons[std::size_t(e.code)];
            if (down == e.down) continue; // no change
            if (moved || buttonChanged || keysChanged.any()) break; // a change of its own
            down = e.down;
            buttonChanged = true;
        } else if (e.kind == InputEvent::Kind::Key && e.code >= 0 && e.code < FrameInput::kKeys) {
            bool& down = m_state.keys[std::size_t(e.code)];
            if (down == e.down) continue;
            // One key change a frame: ImGui sees keys as states once a frame (Ctrl released in the frame
            // A is pressed would hide Ctrl+A), and takes a frame's characters before its keys.
            if (keysChanged.any() || typed || buttonChanged) break;
            down = e.down;
            keysChanged[std::size_t(e.code)] = true;
        } else if (e.kind == InputEvent::Kind::Char) {
            m_state.chars.push_back(unsigned(e.code));
            typed = true;
        } else if (e.kind == InputEvent::Kind::Scroll) {
            m_state.scrollX += e.x, m_state.scrollY += e.y;
        }
    }
    return m_state;
}

} // namespace ui
