// FrameStats: the GPU timers (a ring of timestamp laps read back frames later), the counters read back,
// and the stats' text.
#include "splat_renderer_state.h"

namespace renderer {

// Timestamps the start of `pass` in the frame being timed (nothing when the pass goes on); no pass:
// the frame's start or end.
void SplatRenderer::Gl::lap(std::optional<GpuPass> pass) {
    if (!timing || (pass && pass == lapPass)) return;
    Laps& l = *timing;
    if (l.used == l.queries.size()) {
        GLuint q = 0;
        glCreateQueries(GL_TIMESTAMP, 1, &q);
        l.queries.push_back(q);
        l.passes.emplace_back();
    }
    glQueryCounter(l.queries[l.used], GL_TIMESTAMP);
    l.passes[l.used++] = pass;
    lapPass = pass;
}

void SplatRenderer::Gl::beginTiming(const SplatSettings& settings, FrameStats& stats) {
    stats.frame = ++renders;
    firstUses = 0;
    const size_t slot = size_t(timerNext);
    stats.timed = !timerPending[slot];   // ring full of unfinished frames: skip, never stall
    if (stats.timed) {
        timing = &laps[slot];
        timing->used = 0;
        lapPass.reset();
        lap(std::nullopt);   // the frame's start
    }
    if (settings.counters) glBeginQuery(GL_SAMPLES_PASSED, fragmentQuery);
}

void SplatRenderer::Gl::endTiming(const FramePlan& f) {
    if (f.pointSlices > 0) glDisable(GL_PROGRAM_POINT_SIZE);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    if (f.settings.counters) glEndQuery(GL_SAMPLES_PASSED);
    if (timing) {   // timed: the slot beginTiming() took
        const size_t slot = size_t(timerNext);
        lap(std::nullopt);   // the frame's end
        timing = nullptr;
        timerPending[slot] = true;
        timerFrame[slot] = renders;
        timerFirstUses[slot] = firstUses;
        timerNext = (timerNext + 1) % kTimerRing;
    }
}

void SplatRenderer::Gl::readCounters(FrameStats& stats) {
    GLuint64 fragments = 0;
    glGetQueryObjectui64v(fragmentQuery, GL_QUERY_RESULT, &fragments);
    stats.fragments = fragments;
    std::array<GLuint, kCounterSlots> c{};
    readBuffer(counterBuffer, 0, sizeof(c), c.data());
    SplatCounters& out = stats.counters;
    out = {};
    out.visible = c[kVisible];
    out.culledTransparent = c[kTransparent];
    out.culledNear = c[kNear];
    out.culledDegenerate = c[kDegenerate];
    out.culledHuge = c[kHuge];
    out.culledOffscreen = c[kOffscreen];
    out.drawn = c[kDrawn];
    out.culledOccluded = c[kOccluded];
    for (int m = 0; m < 3; ++m) out.drawnPerMode[m] = c[size_t(kMode0 + m)];
    readNearCounters(out);
}

void SplatRenderer::collectTimers() {
    Gl& g = *m_gl;
    for (int i = 0; i < kTimerRing; ++i) {
        if (!g.timerPending[size_t(i)]) continue;
        const Gl::Laps& laps = g.laps[size_t(i)];
        GLint ready = 0;   // the frame's end, its last query
        glGetQueryObjectiv(laps.queries[laps.used - 1], GL_QUERY_RESULT_AVAILABLE, &ready);
        if (!ready) continue;
        g.timerPending[size_t(i)] = false;
        if (g.timerFrame[size_t(i)] <= g.newestTimed) continue;   // keep the newest finished frame's times
        g.newestTimed = g.timerFrame[size_t(i)];
        std::vector<GLuint64> t(laps.used);
        for (size_t j = 0; j < laps.used; ++j) glGetQueryObjectui64v(laps.queries[j], GL_QUERY_RESULT, &t[j]);
        m_stats.gpuFrame = g.timerFrame[size_t(i)];
        m_stats.gpuFirstUsePrograms = g.timerFirstUses[size_t(i)];
        m_stats.gpuMs = double(t.back() - t.front()) * 1e-6;
        m_stats.passMs = {};
        for (size_t j = 0; j + 1 < laps.used; ++j)
            if (laps.passes[j]) m_stats.passMs[size_t(*laps.passes[j])] += double(t[j + 1] - t[j]) * 1e-6;
    }
}

std::string primitiveName(const FrameStats& f) {
    if (f.tiles) return "tiles";
    if (f.pointSlices == 0) return "quads";
    if (f.quadSlices == 0) return "point sprites";
    return "points and quads (quads in " + std::to_string(f.quadSlices) + " of " +
           std::to_string(f.pointSlices + f.quadSlices) + " slices)";
}

std::string tileSplitsText(const FrameStats& f) {
    if (f.tileListSplits == 0) return "";
    return "tile lists went again in fewer slices " + std::to_string(f.tileListSplits) +
           " times: too many entries at once for the list buffer, or on one tile for the driver's loop limit";
}

const char* gpuPassName(GpuPass pass) {
    switch (pass) {
    case GpuPass::Select: return "select buckets";
    case GpuPass::Patches: return "classify patches";
    case GpuPass::Splats: return "splats";
    case GpuPass::Offsets: return "tile offsets";
    case GpuPass::Scatter: return "tile scatter";
    case GpuPass::Composite: return "composite";
    case GpuPass::Opaque: return "opaque map";
    case GpuPass::Resolve: return "resolve";
    }
    return "?";
}

} // namespace renderer
