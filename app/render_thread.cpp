// The render thread (render_thread.h): its loop of tasks and views, the levels of a view, and when a newer
// request supersedes the frame in flight.
#include "render_thread.h"

#include "renderer/errors.h"
#include "renderer/gl/driver_profile.h"
#include "renderer/gl/gl_context.h"
#include "renderer/out_of_memory.h"

#include <epoxy/gl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// RMSE of two RGBA8 images' colour channels, in 0..1 units.
double displayRmse(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (i % 4 == 3) continue;
        const double d = (double(a[i]) - double(b[i])) / 255.0;
        sum += d * d;
        ++n;
    }
    return n ? std::sqrt(sum / double(n)) : 0.0;
}

std::string atSize(const renderer::ImagePlane& plane) {
    return " at " + std::to_string(plane.width) + "x" + std::to_string(plane.height);
}

// The renderer's last image (or heatmap) over the request's background, 8 bits a channel, row 0 at the top.
std::vector<uint8_t> shownPixels(renderer::SplatRenderer& which, const ViewRequest& request, bool heatmap,
                                 const std::string& whose) {
    std::vector<uint8_t> rgba;
    const size_t bytes = size_t(request.plane.width) * size_t(request.plane.height) * 4;
    renderer::namingAllocation(whose, heatmap ? "heatmap's pixels" : "view's pixels", bytes, atSize(request.plane),
                               [&] { rgba.resize(bytes); });
    const unsigned texture = which.displayTexture(request.background.data(), heatmap);
    glGetTextureImage(texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()), rgba.data());
    renderer::checkGlErrors("render thread: the view's pixels");
    return rgba;
}

} // namespace

RenderThread::RenderThread() {
    if (const char* delay = std::getenv("SPLATLAB_RENDER_DELAY_MS")) m_delayMs = std::max(0, std::atoi(delay));
    std::promise<std::string> started;
    std::future<std::string> name = started.get_future();
    m_thread = std::thread([this, p = std::move(started)]() mutable { loop(std::move(p)); });
    try {
        m_glRenderer = name.get();
    } catch (...) {
        m_thread.join();
        throw;
    }
}

RenderThread::~RenderThread() {
    {
        std::lock_guard lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    m_thread.join();
}

double RenderThread::defaultBudgetMs() const {
    return renderer::driverProfile(m_glRenderer).software ? 150.0 : 16.0;
}

void RenderThread::post(std::function<void(Renderers&)> task, bool reportErrors) {
    {
        std::lock_guard lock(m_mutex);
        m_tasks.emplace_back(std::move(task), reportErrors);
    }
    m_wake.notify_all();
}

void RenderThread::setScenes(std::shared_ptr<const renderer::SplatScene> full, Scenes levels) {
    post([this, full, levels](Renderers& r) { uploadScenes(r, full, levels); }, true);
}

void RenderThread::setScenesNow(std::shared_ptr<const renderer::SplatScene> full, Scenes levels) {
    run([this, full, levels](Renderers& r) { uploadScenes(r, full, levels); }).get();
}

void RenderThread::setLuts(const renderer::TfTables& full, std::vector<renderer::TfTables> levels) {
    post(
        [this, full, levels = std::move(levels)](Renderers& r) {
            r.full->setLut(full);
            for (size_t k = 0; k < levels.size() && k < r.levels.size(); ++k)
                r.levels[k]->setLut(levels[k]);
            m_shown.fullLut = full, m_shown.levelLuts = levels;
            showSlabInputs(r);
        },
        true);
}

void RenderThread::setGradients(std::shared_ptr<const renderer::SplatScene> full, Scenes levels) {
    post(
        [this, full, levels](Renderers& r) {
            r.full->setGradients(*full);
            for (size_t k = 0; k < levels.size() && k < r.levels.size(); ++k)
                r.levels[k]->setGradients(*levels[k]);
            m_shown.fullGradients = full, m_shown.levelGradients = levels;
            showSlabInputs(r);
        },
        true);
}

void RenderThread::setLevelScenes(Scenes levels) {
    post(
        [this, levels](Renderers& r) {
            try {
                for (size_t k = 0; k < levels.size() && k < r.levels.size(); ++k)
                    r.levels[k]->setScene(*levels[k]);
            } catch (const std::exception& e) {
                restoreShown(r, e.what());
                throw;
            }
            for (size_t k = 0; k < levels.size() && k < m_shown.levels.size(); ++k)
                m_shown.levels[k] = levels[k];
        },
        true);
}

void RenderThread::uploadScenes(Renderers& r, const std::shared_ptr<const renderer::SplatScene>& full,
                                const Scenes& levels) {
    const std::string previousName = std::exchange(m_sceneName, full->name); // a failure below names it
    try {
        r.full->setScene(*full);
        r.levels.resize(levels.size());
        for (size_t k = 0; k < levels.size(); ++k) {
            if (!r.levels[k]) r.levels[k] = std::make_unique<renderer::SplatRenderer>();
            r.levels[k]->setScene(*levels[k]);
        }
    } catch (const std::exception& e) {
        m_sceneName = previousName;
        restoreShown(r, e.what());
        throw;
    }
    m_shown = {};
    m_shown.full = full, m_shown.levels = levels;
    showSlabInputs(r);
    m_levelMs = {}; // another volume: its times are still to measure
    m_levelRmse = {-1, -1, -1, -1};
}

void RenderThread::restoreShown(Renderers& r, const std::string& failure) {
    if (!m_shown.full) return;
    try {
        r.full->setScene(*m_shown.full);
        r.levels.resize(m_shown.levels.size());
        for (size_t k = 0; k < m_shown.levels.size(); ++k) {
            if (!r.levels[k]) r.levels[k] = std::make_unique<renderer::SplatRenderer>();
            r.levels[k]->setScene(*m_shown.levels[k]);
        }
        if (m_shown.fullGradients) r.full->setGradients(*m_shown.fullGradients);
        for (size_t k = 0; k < m_shown.levelGradients.size() && k < r.levels.size(); ++k)
            r.levels[k]->setGradients(*m_shown.levelGradients[k]);
        if (m_shown.fullLut) r.full->setLut(*m_shown.fullLut);
        for (size_t k = 0; k < m_shown.levelLuts.size() && k < r.levels.size(); ++k)
            r.levels[k]->setLut(m_shown.levelLuts[k]);
        showSlabInputs(r);
    } catch (const std::exception& e) {
        m_shown = {}; // nothing left to put back; the error says so
        showSlabInputs(r);
        throw renderer::RenderError(failure + "; the previous volume could not be put back on the GPU either: " +
                                    e.what());
    }
}

uint64_t RenderThread::requestView(const ViewRequest& request) {
    uint64_t id = 0;
    {
        std::lock_guard lock(m_mutex);
        id = m_nextId++;
        m_pendingView.emplace(id, request);
        m_newestId = id;
    }
    m_wake.notify_all();
    return id;
}

std::optional<RenderedView> RenderThread::takeView() {
    std::lock_guard lock(m_mutex);
    return std::exchange(m_finished, std::nullopt);
}

void RenderThread::waitForView(uint64_t id) {
    std::unique_lock lock(m_mutex);
    m_viewDone.wait(lock, [&] { return m_doneId >= id || m_stop; });
}

bool RenderThread::busy() const {
    std::lock_guard lock(m_mutex);
    return m_pendingView || m_inFlight != 0;
}

renderer::FrameStats RenderThread::latestStats() const {
    std::lock_guard lock(m_mutex);
    return m_latestStats;
}

std::optional<std::string> RenderThread::takeError() {
    std::lock_guard lock(m_mutex);
    if (m_errors.empty()) return std::nullopt;
    std::string error = std::move(m_errors.front());
    m_errors.pop_front();
    return error;
}

void RenderThread::loop(std::promise<std::string> started) {
    // The context and the renderers live and die on this thread: GL objects go while it is current.
    std::unique_ptr<renderer::HeadlessGl> gl;
    Renderers r;
    // Below the UI thread's priority, and so are the driver threads this thread starts (a new thread
    // inherits its creator's nice value): on a CPU driver the render and the UI share the cores, and the
    // UI's frame must stay short. Failing to lower it costs only that.
    setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 10);
    try {
        gl = renderer::HeadlessGl::create();
        r.full = std::make_unique<renderer::SplatRenderer>();
        started.set_value(renderer::glRendererName());
    } catch (...) {
        started.set_exception(std::current_exception());
        return;
    }
    std::unique_lock lock(m_mutex);
    while (!m_stop) {
        // Idle: collect the GPU timers every 50 ms for the Performance panel.
        if (!m_wake.wait_for(lock, std::chrono::milliseconds(50),
                             [&] { return m_stop || !m_tasks.empty() || m_pendingView; })) {
            lock.unlock();
            r.full->collectTimers();
            lock.lock();
            m_latestStats = r.full->stats();
            continue;
        }
        if (m_stop) break;
        if (!m_tasks.empty()) { // scene changes first: a view asked after them needs them
            auto [task, report] = std::move(m_tasks.front());
            m_tasks.pop_front();
            lock.unlock();
            try {
                task(r);
            } catch (const std::bad_alloc&) { // what the renderer did not name itself
                lock.lock();
                if (report) m_errors.push_back(unnamedOutOfMemory("a scene change"));
                continue;
            } catch (const std::exception& e) {
                lock.lock();
                if (report) m_errors.push_back(e.what());
                continue;
            }
            lock.lock();
            continue;
        }
        auto [id, request] = std::move(*m_pendingView);
        m_pendingView.reset();
        m_inFlight = id;
        lock.unlock();
        try {
            const std::vector<int> levels = levelsToDraw(request, int(r.levels.size()));
            // Slabs after the full frame only: a far view's level or a preview is not the view's last word.
            const bool slabsFollow = request.slabs && levels.back() == 0 && request.others.empty();
            bool drawn = true;
            for (size_t i = 0; i < levels.size() && drawn; ++i)
                drawn = renderLevel(r, levels[i], id, request, i > 0, i + 1 == levels.size());
            if (drawn && slabsFollow) renderSlabs(r, id, request);
        } catch (const std::bad_alloc&) {
            const std::string error = unnamedOutOfMemory("drawing the view");
            std::lock_guard errorLock(m_mutex);
            m_errors.push_back(error);
        } catch (const std::exception& e) {
            std::lock_guard errorLock(m_mutex);
            m_errors.push_back(e.what());
        }
        lock.lock();
        m_inFlight = 0;
        m_doneId = std::max(m_doneId, id);
        m_viewDone.notify_all();
    }
    m_stop = true;
    m_viewDone.notify_all();
    lock.unlock();
    r = {}; // the renderers before the context
}

void RenderThread::showSlabInputs(Renderers& r) const {
    r.slabs.setInputs(m_shown.full, m_shown.fullGradients, m_shown.fullLut);
}

std::string RenderThread::unnamedOutOfMemory(const char* doing) const {
    return renderer::volumeSubject(m_sceneName) + ": out of memory on the render thread " + doing +
           " (the last image stays)";
}

bool RenderThread::superseded(uint64_t id, Clock::time_point started, double budgetMs, bool refinement) const {
    std::lock_guard lock(m_mutex);
    if (m_stop) return true;
    if (m_newestId <= id) return false;
    // A refinement goes at once (its request already showed an image); a first image only once it has
    // missed the budget, so that a stream of edits (a drag) still shows frames that fit it.
    return refinement || msSince(started) > budgetMs;
}

std::vector<int> RenderThread::levelsToDraw(const ViewRequest& request, int levels) const {
    using Levels = ViewRequest::Levels;
    if (request.levels == Levels::FinestOnly && levels > 0) return {1};
    const int finest = std::clamp(request.finestLevel, 0, levels);
    if (finest == levels || request.levels == Levels::FullOnly) return {finest};
    // A level's time: its last, or (not drawn since the scene came) the full frame's over 8 per halving.
    auto estimate = [&](int k) {
        return m_levelMs[size_t(k)] > 0.0 ? m_levelMs[size_t(k)]
               : m_levelMs[0] > 0.0       ? m_levelMs[0] / std::pow(8.0, k)
                                          : HUGE_VAL;
    };
    // The first image: the view's finest level (the full frame, but for a far view) if it fits the budget,
    // else the finest level that fits (none known: the coarsest).
    int first = levels;
    for (int k = finest; k <= levels; ++k)
        if (estimate(k) <= request.budgetMs) {
            first = k;
            break;
        }
    // Then finer levels up to the full frame, each only where it takes at most a quarter of the full
    // frame's time: every frame has a fixed cost (clearing and compositing the image, reading it back), so
    // a level near the full frame's time only delays it.
    std::vector<int> order{first};
    for (int k = first - 1; k > finest; --k)
        if (estimate(k) <= 0.25 * estimate(finest)) order.push_back(k);
    if (first > finest) order.push_back(finest);
    return order;
}

bool RenderThread::renderLevel(Renderers& r, int level, uint64_t id, const ViewRequest& request,
                               bool refinement, bool last) {
    renderer::SplatRenderer& which = level == 0 ? *r.full : *r.levels[size_t(level - 1)];
    const Clock::time_point started = Clock::now();
    for (int waited = 0; waited < m_delayMs; waited += 10) { // SPLATLAB_RENDER_DELAY_MS: a slow scan
        if (superseded(id, started, request.budgetMs, refinement)) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    // The interrupt reads this frame's locals: it goes when the frame ends, whatever ends it.
    struct InterruptScope {
        renderer::SplatRenderer& renderer;
        ~InterruptScope() { renderer.setInterrupt({}); }
    } scope{which};
    which.setInterrupt([&] { return superseded(id, started, request.budgetMs, refinement); });
    const auto renderPane = [&](const renderer::SplatSettings& full, const std::vector<renderer::SplatSettings>& coarse) {
        try {
            which.render(request.plane, level == 0 ? full : coarse[size_t(level - 1)]);
            return true;
        } catch (const renderer::Cancelled&) {
            return false;
        }
    };
    RenderedView view;
    view.request = id;
    view.level = level;
    view.finestLevel = std::clamp(request.finestLevel, 0, int(r.levels.size()));
    view.last = last;
    view.width = request.plane.width, view.height = request.plane.height;
    view.plane = request.plane;
    view.truthKey = request.truthKey;
    const std::string whose = renderer::volumeSubject(m_sceneName);
    // The image, and the heatmap when asked: the viewport blends them, so an opacity change draws no frame.
    const auto pixels = [&](bool heatmap) { return shownPixels(which, request, heatmap, whose); };
    // The split view's other panes first (D, C, B), with the same renderer, so that its last frame (the
    // stats, the timers the Stats panel collects) is the first pane's; |A - B| from the two float images.
    renderer::Image second;
    view.otherRgba.resize(request.others.size());
    for (size_t i = request.others.size(); i-- > 0;) {
        if (!renderPane(request.others[i].full, request.others[i].coarse)) return false;
        view.otherRgba[i] = pixels(false);
        if (i == 0 && request.difference) second = which.readback();
    }
    if (!renderPane(request.full, request.coarse)) return false;
    view.rgba = pixels(false);
    if (request.heatmap) view.heatmapRgba = pixels(true);
    if (request.difference || request.keepFirstPane) {
        renderer::Image first = which.readback();
        if (!request.others.empty() && request.difference) view.difference = ui::differencePane(first, second);
        if (request.keepFirstPane) view.firstPane = std::move(first);
    }
    view.stats = which.stats();
    view.sceneBytes = which.sceneBytes();
    view.workingBytes = which.workingBytes();
    m_levelMs[size_t(level)] = msSince(started);
    // Each level's error against the full frame that follows it in the same request.
    if (m_levelPixelsOf != id) {
        for (auto& pixels : m_levelPixels) pixels.clear();
        m_levelPixelsOf = id;
    }
    if (level > 0) {
        renderer::namingAllocation(whose, "copy of a level's pixels", view.rgba.size(), atSize(request.plane),
                                   [&] { m_levelPixels[size_t(level)] = view.rgba; });
    } else {
        for (int k = 1; k < kMaxViewLevels; ++k)
            if (m_levelPixels[size_t(k)].size() == view.rgba.size())
                m_levelRmse[size_t(k)] = displayRmse(m_levelPixels[size_t(k)], view.rgba);
    }
    view.levelMs = m_levelMs;
    view.levelRmse = m_levelRmse;
    if (level == 0) {
        std::lock_guard lock(m_mutex);
        m_latestStats = view.stats;
    }
    finish(std::move(view));
    return true;
}

void RenderThread::renderSlabs(Renderers& r, uint64_t id, const ViewRequest& request) {
    const Clock::time_point started = Clock::now();
    renderer::Image image;
    try {
        image = r.slabs.render(request.plane, request.full, *request.slabs,
                               [&] { return superseded(id, started, request.budgetMs, true); });
    } catch (const renderer::Cancelled&) {
        return;
    } catch (const renderer::RenderError& e) { // a setting the slabs do not take: the sheets stay, saying why
        std::lock_guard lock(m_mutex);
        m_slabNote = e.what();
        return;
    }
    RenderedView view;
    view.request = id;
    view.width = request.plane.width, view.height = request.plane.height;
    view.plane = request.plane;
    view.truthKey = request.truthKey;
    view.slabs = true; // after the view's last image: `last` as that one's
    view.rgba = displayPixels(image, request.background.data());
    // The heatmap is of the patches' filters, which the slabs take as the sheets did: the full frame's.
    if (request.heatmap) view.heatmapRgba = shownPixels(*r.full, request, true, renderer::volumeSubject(m_sceneName));
    if (request.keepFirstPane) view.firstPane = std::move(image);
    view.stats = r.full->stats();
    view.sceneBytes = r.full->sceneBytes();
    view.workingBytes = r.full->workingBytes();
    view.levelMs = m_levelMs;
    view.levelRmse = m_levelRmse;
    view.slabMs = msSince(started);
    {
        std::lock_guard lock(m_mutex);
        m_slabNote.clear();
    }
    finish(std::move(view));
}

void RenderThread::finish(RenderedView view) {
    std::function<void()> onImage;
    {
        std::lock_guard lock(m_mutex);
        m_finished = std::move(view);
        onImage = m_onImage;
    }
    if (onImage) onImage();
}

std::string RenderThread::slabNote() const {
    std::lock_guard lock(m_mutex);
    return m_slabNote;
}
