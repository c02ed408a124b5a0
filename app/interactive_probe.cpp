// InteractiveProbe (interactive_probe.h): the edits it makes, what it records, and its report.
#include "interactive_probe.h"

#include "renderer/math/metrics.h"

#include <algorithm>
#include <cstdio>

namespace {

double msBetween(InteractiveProbe::Clock::time_point a, InteractiveProbe::Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

} // namespace

bool InteractiveProbe::editDue(Clock::time_point now) const {
    return m_sawFull && !m_waiting && int(m_firstMs.size()) < m_edits && msBetween(m_fullAt, now) > 250.0;
}

void InteractiveProbe::editMade(Clock::time_point now) {
    m_editAt = now;
    m_waiting = true;
    m_firstSeen = false;
    m_request = 0;
}

void InteractiveProbe::requested(uint64_t request) {
    if (m_waiting && m_request == 0) m_request = request;
}

void InteractiveProbe::imageShown(uint64_t request, int level, int finestLevel, Clock::time_point now) {
    const bool own = level <= finestLevel;   // the view's last image: the full frame, or a far view's level
    if (own && !m_waiting) { // the volume's own first frame, before any edit
        m_sawFull = true;
        m_fullAt = now;
        return;
    }
    if (!m_waiting || m_request == 0 || request < m_request) return;
    if (!m_firstSeen) {
        m_firstSeen = true;
        m_firstMs.push_back(msBetween(m_editAt, now));
        m_firstLevel.push_back(level - finestLevel);   // levels coarser than the view's own
    }
    if (own) {
        m_fullMs.push_back(msBetween(m_editAt, now));
        m_waiting = false;
        m_fullAt = now;
    }
}

void InteractiveProbe::uiFrame(double ms, bool rendering) {
    if (rendering && m_sawFull) m_uiMs.push_back(ms);
}

std::string InteractiveProbe::report(const std::string& volume, const std::vector<double>& levelMs,
                                     const std::vector<double>& levelRmse) const {
    int coarse = 0, levelSum = 0;
    for (int level : m_firstLevel) coarse += level > 0, levelSum += level;
    const auto q = [](const std::vector<double>& values, double p) { return renderer::nearestRankQuantile(values, p); };
    char text[1024];
    std::snprintf(text, sizeof text,
                  "interactive %s: %zu edits (the camera turned 10 degrees each)\n"
                  "  edit to first image %.1f ms median (p10 %.1f, p90 %.1f); from a coarser level in %d of them\n"
                  "  edit to full frame  %.1f ms median (p10 %.1f, p90 %.1f)\n"
                  "  UI frame while rendering %.1f ms median, p95 %.1f, max %.1f (%zu frames)\n",
                  volume.c_str(), m_firstMs.size(), q(m_firstMs, 0.5), q(m_firstMs, 0.1),
                  q(m_firstMs, 0.9), coarse, q(m_fullMs, 0.5), q(m_fullMs, 0.1),
                  q(m_fullMs, 0.9), q(m_uiMs, 0.5), q(m_uiMs, 0.95), q(m_uiMs, 1.0),
                  m_uiMs.size());
    std::string out = text;
    std::snprintf(text, sizeof text,
                  "interactive_result volume=%s edits=%zu first_image_ms=%.2f first_image_p10_ms=%.2f "
                  "first_image_p90_ms=%.2f first_level_mean=%.2f full_ms=%.2f full_p10_ms=%.2f full_p90_ms=%.2f "
                  "ui_p50_ms=%.2f ui_p95_ms=%.2f ui_max_ms=%.2f ui_frames=%zu",
                  volume.c_str(), m_firstMs.size(), q(m_firstMs, 0.5), q(m_firstMs, 0.1),
                  q(m_firstMs, 0.9), m_firstLevel.empty() ? 0.0 : double(levelSum) / double(m_firstLevel.size()),
                  q(m_fullMs, 0.5), q(m_fullMs, 0.1), q(m_fullMs, 0.9), q(m_uiMs, 0.5),
                  q(m_uiMs, 0.95), q(m_uiMs, 1.0), m_uiMs.size());
    out += text;
    for (size_t k = 0; k < levelMs.size(); ++k)
        if (levelMs[k] > 0.0) {
            std::snprintf(text, sizeof text, " level%zu_ms=%.2f", k, levelMs[k]);
            out += text;
        }
    for (size_t k = 1; k < levelRmse.size(); ++k)
        if (levelRmse[k] >= 0.0) {
            std::snprintf(text, sizeof text, " level%zu_rmse=%.5f", k, levelRmse[k]);
            out += text;
        }
    return out + "\n";
}
