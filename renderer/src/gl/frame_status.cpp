// The GPU profile's tiled frames read nothing back while they run (DriverProfile::deferredListChecks):
// tile_bases.comp leaves each frame's figures in one of two status buffers, read once a fence says the
// frame has finished. They size the lists of the frames after it and say whether its own image is whole.
#include "splat_renderer_state.h"

#include <algorithm>
#include <cmath>

namespace renderer {

namespace {

// FrameStatus in tile_bases.comp: the most entries a part took, the frame's entries, the most loop
// trips a tile's composite took, whether a record invocation was cut short.
constexpr GLsizeiptr kStatusBytes = 4 * sizeof(GLuint);
// Room above the most entries seen, so that a view turning a little does not overflow at once.
constexpr double kCapacityHeadroom = 1.25;

bool finished(GLsync fence) {
    const GLenum r = glClientWaitSync(fence, 0, 0);
    return r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED;
}

} // namespace

SplatRenderer::Gl::StatusSlot& SplatRenderer::Gl::beginStatus() {
    StatusSlot& slot = statusSlots[size_t(statusNext)];
    if (slot.pending) {   // a frame two back that nobody consumed: what it left if it has finished, else dropped
        if (finished(slot.fence)) takeStatus(slot, nullptr);
        glDeleteSync(slot.fence);
        slot = StatusSlot{slot.buffer};
    }
    if (!slot.buffer) {
        glCreateBuffers(1, &slot.buffer);
        glNamedBufferStorage(slot.buffer, kStatusBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    if (!scatterArgs) {
        glCreateBuffers(1, &scatterArgs);
        glNamedBufferStorage(scatterArgs, 4 * sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    glClearNamedBufferData(slot.buffer, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 13, slot.buffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 14, scatterArgs);
    return slot;
}

void SplatRenderer::Gl::endStatus(StatusSlot& slot, uint64_t capacity, GLuint segments, bool deferred) {
    if (!deferred) return;   // the checked way read its figures as it went; the slot is free again
    slot.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();   // a fence polled without waiting signals only once the commands before it were sent
    slot.pending = true;
    slot.capacity = capacity;
    slot.segments = segments;
    statusLatest = statusNext;
    statusNext ^= 1;
}

void SplatRenderer::Gl::pollStatus() {
    for (StatusSlot& slot : statusSlots)
        if (slot.pending && finished(slot.fence)) takeStatus(slot, nullptr);
}

bool SplatRenderer::Gl::takeStatus(StatusSlot& slot, FrameStats* stats) {
    if (!slot.pending) return false;
    // Not counted in readBacks: a finished frame's (pollStatus), or the one being consumed, which the
    // image's own read or display waits for anyway.
    GLuint figures[4] = {0, 0, 0, 0};
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(slot.buffer, 0, kStatusBytes, figures);
    glDeleteSync(slot.fence);
    slot.fence = nullptr;
    slot.pending = false;
    const uint64_t most = figures[0];
    listCapacity = std::max(listCapacity, uint64_t(std::ceil(double(most) * kCapacityHeadroom)));
    if (figures[3]) recordSegments = std::min(kMaxRunSegments, std::max(recordSegments, slot.segments * 8));
    if (stats) stats->tileEntries = figures[1];
    return most > slot.capacity || figures[3] != 0 || (loopLimit && figures[2] > loopLimit);
}

} // namespace renderer
