// Recent renders' timings for the Performance panel: plain data, no GL and no ImGui. A render's GPU
// times arrive a few renders after it (the timer ring never stalls; FrameStats::gpuFrame says which
// render they are of), so a render waits here until its times come, then joins the history.
#pragma once
#include "renderer/gl/splat_renderer.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>

namespace ui {

struct PerfSample {
    uint64_t frame = 0;        // FrameStats::frame
    double intervalMs = 0.0;   // from the previous render's start to this one's (0: not back to back)
    double cpuMs = 0.0, gpuMs = 0.0;
    std::array<double, renderer::kGpuPasses> passMs{};
    uint64_t splats = 0, uploadBytes = 0;
    int firstUsePrograms = 0;   // FrameStats::firstUsePrograms: its times include compiling shaders
};

// Medians and spreads over the history. p95: the nearest-rank 95th percentile.
struct PerfSummary {
    size_t renders = 0;
    double gpuMedianMs = 0.0, gpuP95Ms = 0.0, gpuMinMs = 0.0, gpuMaxMs = 0.0;
    double cpuMedianMs = 0.0;
    size_t intervals = 0;            // renders that followed another back to back
    double intervalMedianMs = 0.0;   // of those: 1000 / it is the renders a second the user sees
    double splatsPerSecond = 0.0;    // the median render's splats over the median GPU time
    std::array<double, renderer::kGpuPasses> passMedianMs{};
};

// "splats 9.10 ms" for each pass that took time, joined by `separator`.
std::string passListText(const std::array<double, renderer::kGpuPasses>& passMs, const std::string& separator);

// The summary as plain text for a report (the Performance panel's Copy): `context` first (what was
// rendered, where), then the figures the panel shows, in milliseconds.
std::string summaryText(const PerfSummary& summary, const std::string& context);

// What a render's figures are of, for summaryText: the volume and its size, the image size, filter,
// compositing (with the primitive `frame` used) and what changes the work from the defaults (shading,
// surface splats, early termination or occlusion culling turned off), then GL_RENDERER.
std::string renderContext(const std::string& volume, glm::ivec3 dims, glm::ivec2 imageSize,
                          const renderer::SplatSettings& settings, const renderer::FrameStats& frame,
                          const std::string& glRenderer);

class PerfHistory {
public:
    static constexpr size_t kCapacity = 240;   // renders kept: the oldest leave first
    static constexpr size_t kPending = 16;     // renders waiting for their times (more than the ring)

    // After a render: its CPU time, splats and upload; `intervalMs` as PerfSample's.
    void addRender(const renderer::FrameStats& f, double intervalMs);
    // After FrameStats's GPU times changed (collectTimers): joins them to their render, once.
    void addTimes(const renderer::FrameStats& f);
    void clear();
    // Paused, the recorded renders stay as they are while rendering goes on: new renders and times are
    // dropped (the Performance panel's Pause, to inspect a moment). Resuming starts joining afresh.
    void setPaused(bool paused);
    bool paused() const { return m_paused; }
    const std::deque<PerfSample>& samples() const { return m_samples; }
    PerfSummary summary() const;

private:
    std::deque<PerfSample> m_pending, m_samples;
    uint64_t m_lastTimed = 0;
    bool m_paused = false;
};

} // namespace ui
