#include "ui/perf_history.h"

#include "renderer/math/ewa.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace ui {

namespace {

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    const size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
    if (v.size() % 2) return v[mid];
    const double upper = v[mid];
    return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(mid)));
}

} // namespace

void PerfHistory::addRender(const renderer::FrameStats& f, double intervalMs) {
    if (m_paused) return;
    PerfSample s;
    s.frame = f.frame;
    s.intervalMs = intervalMs;
    s.cpuMs = f.cpuMs;
    s.splats = f.splatsDrawn;
    s.uploadBytes = f.frameUploadBytes;
    s.firstUsePrograms = f.firstUsePrograms;
    m_pending.push_back(s);
    if (m_pending.size() > kPending) m_pending.pop_front();   // its times were never taken (ring full)
}

void PerfHistory::addTimes(const renderer::FrameStats& f) {
    if (m_paused) return;
    if (f.gpuFrame == 0 || f.gpuFrame <= m_lastTimed) return;
    m_lastTimed = f.gpuFrame;
    // Renders older than the timed one will get no times (collectTimers keeps the newest): drop them.
    while (!m_pending.empty() && m_pending.front().frame < f.gpuFrame) m_pending.pop_front();
    if (m_pending.empty() || m_pending.front().frame != f.gpuFrame) return;
    PerfSample s = m_pending.front();
    m_pending.pop_front();
    s.gpuMs = f.gpuMs;
    s.passMs = f.passMs;
    m_samples.push_back(s);
    if (m_samples.size() > kCapacity) m_samples.pop_front();
}

void PerfHistory::setPaused(bool paused) {
    if (m_paused && !paused) m_pending.clear();   // renders from before the pause: their times are stale
    m_paused = paused;
}

void PerfHistory::clear() {
    m_pending.clear();
    m_samples.clear();
}

PerfSummary PerfHistory::summary() const {
    PerfSummary out;
    out.renders = m_samples.size();
    if (m_samples.empty()) return out;
    std::vector<double> gpu, cpu, intervals, splats;
    for (const PerfSample& s : m_samples) {
        gpu.push_back(s.gpuMs);
        cpu.push_back(s.cpuMs);
        splats.push_back(double(s.splats));
        if (s.intervalMs > 0.0) intervals.push_back(s.intervalMs);
    }
    out.gpuMedianMs = median(gpu);
    out.cpuMedianMs = median(cpu);
    out.intervals = intervals.size();
    out.intervalMedianMs = median(intervals);
    std::sort(gpu.begin(), gpu.end());
    out.gpuMinMs = gpu.front();
    out.gpuMaxMs = gpu.back();
    out.gpuP95Ms = gpu[size_t(std::ceil(0.95 * double(gpu.size()))) - 1];
    if (out.gpuMedianMs > 0.0) out.splatsPerSecond = median(splats) / (out.gpuMedianMs * 1e-3);
    for (int p = 0; p < renderer::kGpuPasses; ++p) {
        std::vector<double> pass;
        for (const PerfSample& s : m_samples) pass.push_back(s.passMs[size_t(p)]);
        out.passMedianMs[size_t(p)] = median(pass);
    }
    return out;
}

std::string passListText(const std::array<double, renderer::kGpuPasses>& passMs, const std::string& separator) {
    std::string text;
    for (int p = 0; p < renderer::kGpuPasses; ++p)
        if (const double ms = passMs[size_t(p)]; ms > 0.0) {
            char item[64];
            std::snprintf(item, sizeof item, "%s %.2f ms", renderer::gpuPassName(renderer::GpuPass(p)), ms);
            text += (text.empty() ? "" : separator) + item;
        }
    return text;
}

std::string renderContext(const std::string& volume, glm::ivec3 dims, glm::ivec2 imageSize,
                          const renderer::SplatSettings& s, const renderer::FrameStats& frame,
                          const std::string& glRenderer) {
    using renderer::Compositing;
    std::string text = volume + " " + std::to_string(dims.x) + "x" + std::to_string(dims.y) + "x" +
                       std::to_string(dims.z) + ", " + std::to_string(imageSize.x) + "x" +
                       std::to_string(imageSize.y) + " px, " + renderer::filterModeName(s.filter) + ", " +
                       renderer::compositingName(s.compositing) + " (" + renderer::primitiveName(frame) + ")";
    if (s.shading != renderer::SplatSettings::Shading::None)
        text += std::string(", shaded ") + renderer::shadingName(s.shading);
    if (s.surfaceFlatten != 1.0) text += ", surface splats";
    // Early termination and culling act front to back (splat-every-sample turns back to front without them).
    if (s.compositing == Compositing::SheetFrontToBack && s.opaqueAlpha >= 1.0) text += ", no early termination";
    else if (renderer::frontToBack(s) && s.opaqueAlpha < 1.0 && !s.occlusionCulling) text += ", no occlusion culling";
    return text + ", " + glRenderer;
}

std::string summaryText(const PerfSummary& s, const std::string& context) {
    char line[256];
    std::string text = "SplatLab performance: " + context + "\n";
    std::snprintf(line, sizeof line,
                  "%zu renders: GPU median %.2f ms (%.1f /s), p95 %.2f, min %.2f, max %.2f ms; CPU median %.2f ms\n",
                  s.renders, s.gpuMedianMs, s.gpuMedianMs > 0.0 ? 1000.0 / s.gpuMedianMs : 0.0, s.gpuP95Ms, s.gpuMinMs,
                  s.gpuMaxMs, s.cpuMedianMs);
    text += line;
    if (s.intervals > 0) std::snprintf(line, sizeof line, "renders seen %.1f /s; ", 1000.0 / s.intervalMedianMs);
    else std::snprintf(line, sizeof line, "renders seen: none back to back; ");
    text += line;
    std::snprintf(line, sizeof line, "splats sent %.3g /s\npasses (medians): ", s.splatsPerSecond);
    return text + line + passListText(s.passMedianMs, ", ") + "\n";
}

} // namespace ui
