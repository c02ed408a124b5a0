// The split view's ground truth on a worker (split_truth.h): coarse, then at the pane's size; a newer view
// cancels it.
#include "split_truth.h"

#include "renderer/errors.h"
#include "renderer/oracle/ground_truth.h"
#include "ui/split_view.h"

#include <sys/resource.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>

struct SplitTruth::Job {
    std::string key;
    std::atomic<bool> cancel{false}, done{false};
    mutable std::mutex mutex;
    std::optional<Truth> truth; // the finest so far
    std::optional<std::string> error;
    bool coarseDone = false;
    std::thread thread;
};

namespace {

// A quarter of the pane's size per axis, at least 1 x 1: a sixteenth of the rays.
constexpr int kCoarseDivisor = 4;

// The truth's rays are traced by TBB's worker threads, which the process shares and which run at the
// priority of whoever started them (the UI's). In the truth's own arena each thread that joins it is
// lowered below the render thread (nice 10) for as long as it works there, so on a CPU driver the view
// and the UI keep the cores they need; a thread's old priority comes back when it leaves, where the
// system allows raising it again (else it stays low: background work either way).
class LowPriorityArena : public tbb::task_scheduler_observer {
  public:
    explicit LowPriorityArena(tbb::task_arena& arena) : tbb::task_scheduler_observer(arena) { observe(true); }
    ~LowPriorityArena() override { observe(false); }
    void on_scheduler_entry(bool) override {
        errno = 0;
        const int now = getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
        previous() = errno == 0 ? now : 0;
        setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 15);
    }
    void on_scheduler_exit(bool) override {
        setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), previous());
    }

  private:
    static int& previous() {
        thread_local int value = 0;
        return value;
    }
};

} // namespace

SplitTruth::SplitTruth(std::filesystem::path cacheDir, Clock::duration rest, bool lowPriority)
    : m_cacheDir(std::move(cacheDir)), m_rest(rest), m_lowPriority(lowPriority) {
    if (const char* delay = std::getenv("SPLATLAB_TRUTH_DELAY_MS")) m_delayMs = std::max(0, std::atoi(delay));
}

SplitTruth::~SplitTruth() {
    clear();
    for (const std::shared_ptr<Job>& job : m_retired)
        if (job->thread.joinable()) job->thread.join();
}

std::string SplitTruth::viewKey(const renderer::ImagePlane& p, const renderer::SplatSettings& s,
                                uint64_t sceneVersion) {
    // Exact (hex) floats: a key differs when anything the truth depends on does (groundTruthKey's fields
    // bar the scene's voxels, which the version stands for).
    std::string key;
    const auto add = [&](double v) {
        char text[32];
        std::snprintf(text, sizeof text, "%a,", v);
        key += text;
    };
    add(sceneVersion), add(p.width), add(p.height), add(p.fPx), add(p.orthographic), add(p.tanHalfFovY);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            add(p.viewFromObject[i][j]);
    for (int i = 0; i < 3; ++i)
        add(p.translation[i]);
    add(p.centrePx.x), add(p.centrePx.y), add(p.nearDepth);
    add(s.kernelScale), add(s.cutoffSigmas), add(s.density),
        add(s.compositing == renderer::Compositing::XRay);
    add(double(s.shading)), add(s.shadingParams.ambient), add(s.shadingParams.diffuse);
    add(s.shadingParams.specular), add(s.shadingParams.shininess), add(s.surfaceFlatten),
        add(s.surfaceGradient);
    return key;
}

void SplitTruth::want(const std::string& key, const renderer::ImagePlane& plane,
                      const renderer::SplatSettings& settings,
                      const std::function<std::shared_ptr<const renderer::SplatScene>()>& scene) {
    reap();
    if (key != m_wantedKey) {
        clear();
        m_wantedKey = key, m_plane = plane, m_settings = settings, m_scene = scene;
        m_wantedSince = Clock::now();
    }
    startPending(false);
}

void SplitTruth::clear() {
    reap();
    if (m_job) {
        m_job->cancel = true;
        m_retired.push_back(std::move(m_job));
    }
    m_job.reset();
    m_wantedKey.clear();
    m_scene = {};
}

void SplitTruth::reap() {
    std::erase_if(m_retired, [](const std::shared_ptr<Job>& job) {
        if (!job->done) return false;
        if (job->thread.joinable()) job->thread.join();
        return true;
    });
}

void SplitTruth::startPending(bool now) {
    if (m_job || m_wantedKey.empty() || (!now && Clock::now() - m_wantedSince < m_rest)) return;
    auto job = std::make_shared<Job>();
    job->key = m_wantedKey;
    const std::shared_ptr<const renderer::SplatScene> scene = m_scene();
    m_scene = {};
    const Clock::time_point started = Clock::now();
    job->thread = std::thread([job, scene, plane = m_plane, settings = m_settings, cacheDir = m_cacheDir,
                               started, delayMs = m_delayMs, low = m_lowPriority] {
        // Below the render thread (10), and so is every TBB thread while it traces this truth's rays.
        if (low) setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 15);
        tbb::task_arena arena;
        arena.initialize();
        std::optional<LowPriorityArena> lowered;
        if (low) lowered.emplace(arena);
        const renderer::ProgressCallback progress = [&](double) { return !job->cancel.load(); };
        for (int waited = 0; waited < delayMs && !job->cancel; waited += 10) // SPLATLAB_TRUTH_DELAY_MS
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        renderer::GroundTruthStats stats;
        const auto compute = [&](const renderer::ImagePlane& at) {
            return cacheDir.empty()
                       ? renderer::renderGroundTruth(*scene, at, settings, {}, progress, &stats)
                       : renderer::cachedGroundTruth(*scene, at, settings, {}, cacheDir, progress, &stats);
        };
        try {
            // The coarse truth: the same view at a quarter of the size (its focal length and principal
            // point scale with it).
            renderer::ImagePlane coarse = plane;
            coarse.width = std::max(1, plane.width / kCoarseDivisor);
            coarse.height = std::max(1, plane.height / kCoarseDivisor);
            const double sx = double(coarse.width) / plane.width, sy = double(coarse.height) / plane.height;
            coarse.fPx = plane.fPx * sy;
            coarse.centrePx = {plane.centrePx.x * sx, plane.centrePx.y * sy};
            for (const renderer::ImagePlane& at : {coarse, plane}) {
                const renderer::Image image = arena.execute([&] { return compute(at); });
                if (job->cancel) break;
                Truth truth{.key = job->key,
                            .image = std::make_shared<const renderer::Image>(
                                at.width == plane.width
                                    ? image
                                    : ui::upsampleBilinear(image, plane.width, plane.height)),
                            .coarse = at.width != plane.width || at.height != plane.height,
                            .computedWidth = at.width,
                            .computedHeight = at.height,
                            .seconds = std::chrono::duration<double>(Clock::now() - started).count(),
                            .cached = stats.fromCache};
                std::lock_guard lock(job->mutex);
                job->truth = std::move(truth);
                job->coarseDone = true;
            }
        } catch (const std::exception& e) {
            std::lock_guard lock(job->mutex);
            if (!job->cancel) job->error = e.what();
        }
        job->done = true;
    });
    m_job = std::move(job);
}

std::optional<SplitTruth::Truth> SplitTruth::latest() const {
    if (!m_job) return std::nullopt;
    std::lock_guard lock(m_job->mutex);
    return m_job->truth;
}

bool SplitTruth::computing() const {
    if (m_wantedKey.empty()) return false;
    if (!m_job) return true;
    std::lock_guard lock(m_job->mutex);
    return !m_job->error && !(m_job->truth && !m_job->truth->coarse) && !m_job->done;
}

bool SplitTruth::coarseComputing() const {
    if (m_wantedKey.empty()) return false;
    if (!m_job) return true;
    std::lock_guard lock(m_job->mutex);
    return !m_job->coarseDone && !m_job->error;
}

std::optional<std::string> SplitTruth::error() const {
    if (!m_job) return std::nullopt;
    std::lock_guard lock(m_job->mutex);
    return m_job->error;
}

void SplitTruth::waitUntilDone() {
    startPending(true);
    if (m_job && m_job->thread.joinable()) m_job->thread.join();
}
