// --measure-interactive N: the editor measures itself as a user meets it. N times it turns the camera by
// 10 degrees (an edit) once the last edit's full frame is on screen (and the volume's gradients are
// computed: steady state), and records the time from the edit
// to its first image (and that image's level), to its full frame, and every UI frame's time while a
// render is in flight. Then it prints medians with their spread and closes the window. The benchmark
// tests/bench/interactive_bench.cpp runs it per volume.
#pragma once
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

class InteractiveProbe {
  public:
    using Clock = std::chrono::steady_clock;
    explicit InteractiveProbe(int edits) : m_edits(edits) {}

    // An edit is due: the volume's first full frame came (its shaders compiled), the last edit's full
    // frame too, and a quarter second has passed since.
    bool editDue(Clock::time_point now) const;
    void editMade(Clock::time_point now);
    void requested(uint64_t request); // the view request the edit asked for
    // An image arrived: level 0 is the full frame; the view's own is finestLevel (a far view rests on a
    // coarser level, RenderedView::finestLevel), which ends an edit as the full frame does.
    void imageShown(uint64_t request, int level, int finestLevel, Clock::time_point now);
    // A UI frame's time, from after its wait for input to its swap; `rendering`: a view was in flight.
    void uiFrame(double ms, bool rendering);
    bool finished() const { return int(m_firstMs.size()) >= m_edits && !m_waiting; }
    // "interactive_result volume=... first_image_ms=... ui_p95_ms=..." and a sentence for people.
    // levelMs, levelRmse: the last view's per level (0: full), as RenderedView gives them.
    std::string report(const std::string& volume, const std::vector<double>& levelMs,
                       const std::vector<double>& levelRmse) const;

  private:
    int m_edits;
    bool m_sawFull = false, m_waiting = false, m_firstSeen = false;
    uint64_t m_request = 0;
    Clock::time_point m_editAt, m_fullAt;
    std::vector<double> m_firstMs, m_fullMs, m_uiMs;
    std::vector<int> m_firstLevel;
};
