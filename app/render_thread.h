// The editor's renderer on a thread of its own, with its own headless GL context (EGL), so the UI thread
// never waits for a frame. It owns the splat renderers (the full scene's and its coarser levels'); the UI
// hands it copies of the scenes and asks for views, and each UI frame takes the newest finished image.
// Progressive: a view's first image comes from the finest level whose measured time fits the frame
// budget, then finer levels replace it up to the full frame. A newer view request supersedes the frame in
// flight at its next chunk (SplatRenderer::setInterrupt). A still view may end in a frame of image-aligned
// slabs (ViewRequest::slabs), after the full frame of sheets.
#pragma once
#include "slab_refinement.h"

#include "renderer/gl/splat_renderer.h"
#include "renderer/oracle/image_slabs.h"
#include "renderer/model/splat_scene.h"
#include "ui/split_view.h"

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

// The renderers the thread owns; tasks (RenderThread::run) get them.
struct Renderers {
    std::unique_ptr<renderer::SplatRenderer> full;
    std::vector<std::unique_ptr<renderer::SplatRenderer>> levels; // 1/2, 1/4, 1/8 per axis; may be none
    SlabRefinement slabs; // image-aligned slab frames of the full scene shown
};

// Levels of detail a view can come from: 0 the full frame, k the level at 1/2^k per axis.
constexpr int kMaxViewLevels = 4;

// What the viewport asks for.
struct ViewRequest {
    renderer::ImagePlane plane;   // the same view at every level
    renderer::SplatSettings full; // settings of the full frame
    std::vector<renderer::SplatSettings> coarse; // of each level, finest first (the same extinction per
                                                 // unit length: renderer::densityFor)
    std::array<float, 3> background{};
    bool heatmap = false; // also the heatmap (RenderedView::heatmapRgba); full.heatmap must be on
    // The split view's other panes (B, then C and D in a four-pane view): the same plane drawn again with
    // each one's settings (of the full frame and of each level, as above), at each level before the first
    // pane; with `difference`, also |A - B|.
    struct OtherPane {
        renderer::SplatSettings full;
        std::vector<renderer::SplatSettings> coarse;
    };
    std::vector<OtherPane> others;
    bool difference = false;     // needs `others`
    bool keepFirstPane = false;  // RenderedView::firstPane: the first pane's float image (|A - truth|)
    std::string truthKey;        // what the first pane's ground truth is of (split_truth.h), handed back
    enum class Levels { Progressive, FullOnly, FinestOnly } levels = Levels::Progressive;
    // A far view's level (EditorLoop::farViewLevel): the finest a Progressive or FullOnly request draws,
    // its image then the view's last; 0: the full frame.
    int finestLevel = 0;
    double budgetMs = 150.0; // a first image within this, from the finest level whose last time fits
    // Then, where the request draws the full frame (not a far view's level) and has one pane: the same
    // view in image-aligned slabs, one more image after its last (RenderedView::slabs). A failure (a
    // setting the slabs do not take) leaves the sheets' frame shown and says why (RenderThread::slabNote).
    std::optional<renderer::SlabOptions> slabs;
};

// One finished image of a request: a level's (then finer ones follow) or the full frame's.
struct RenderedView {
    uint64_t request = 0;
    int level = 0;                    // 0: the full frame; k: the level at 1/2^k per axis
    int finestLevel = 0;              // the finest level the request draws (ViewRequest::finestLevel)
    bool last = true;                 // no finer image of this request follows
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;        // over the background, 8 bits a channel, row 0 at the top
    std::vector<uint8_t> heatmapRgba; // the filter-mode heatmap of the same render, likewise (empty
                                      // unless the request asked for it): the viewport blends the two
    std::vector<std::vector<uint8_t>> otherRgba;  // the split view's other panes, likewise (B, C, D)
    std::optional<ui::DifferencePane> difference; // |A - B| of the two panes' float images, when asked
    std::optional<renderer::Image> firstPane;     // the first pane's float image, when asked
    std::string truthKey;                         // the request's
    renderer::ImagePlane plane;
    bool slabs = false;         // the image-aligned slab frame after the last (ViewRequest::slabs), `last`
                                // as that one; stats, level times and bytes are the sheets' full frame's
    double slabMs = 0.0;        // ...its time
    renderer::FrameStats stats; // of the first pane
    uint64_t sceneBytes = 0, workingBytes = 0;
    // Per level (0: full): its last render and read-back in ms (0: not drawn yet), and the RMSE of its
    // last image against the full frame that replaced it (-1: none yet).
    std::array<double, kMaxViewLevels> levelMs{}, levelRmse{-1, -1, -1, -1};
};

class RenderThread {
  public:
    // Starts the thread and its GL context; throws GlError (from the thread) when there is none.
    RenderThread();
    ~RenderThread(); // the frame in flight stops at its next chunk; queued tasks are dropped
    RenderThread(const RenderThread&) = delete;
    RenderThread& operator=(const RenderThread&) = delete;

    const std::string& glRenderer() const { return m_glRenderer; }
    // The budget for a first image on this driver: 150 ms on llvmpipe, 16 ms on a GPU.
    double defaultBudgetMs() const;

    // Scene changes, run in order before any view asked for after them. Errors come back through takeError.
    using Scenes = std::vector<std::shared_ptr<const renderer::SplatScene>>;
    // A scene change that fails (out of GPU memory, say) puts the scenes shown before back, so the view
    // keeps showing the previous volume.
    void setScenes(std::shared_ptr<const renderer::SplatScene> full, Scenes levels); // forgets the times
    // The same, waiting for it: throws its error (opening a volume: the document changes only once the
    // renderers hold the new one).
    void setScenesNow(std::shared_ptr<const renderer::SplatScene> full, Scenes levels);
    void setLuts(const renderer::TfTables& full, std::vector<renderer::TfTables> levels);
    void setGradients(std::shared_ptr<const renderer::SplatScene> full, Scenes levels);
    void setLevelScenes(Scenes levels); // the window dragged: the levels alone re-classified

    // Asks for a view; replaces a request not yet started and supersedes the frame in flight. Returns its id.
    uint64_t requestView(const ViewRequest& request);
    // The newest image finished since the last call, if any.
    std::optional<RenderedView> takeView();
    // Waits until request `id` gave its last image or failed (scripted runs: deterministic frames).
    void waitForView(uint64_t id);
    bool busy() const; // a view is queued or in flight
    // The full renderer's stats, with GPU times collected since (the Performance panel's per UI frame).
    renderer::FrameStats latestStats() const;
    // A failure of a scene change or a view, oldest first.
    std::optional<std::string> takeError();
    // Why the last slab frame asked for was not drawn ("" when it was, or none was asked for).
    std::string slabNote() const;

    // Runs `task(renderers)` on the thread after what is queued; its result or exception in the future.
    template <class Task> auto run(Task task) -> std::future<decltype(task(std::declval<Renderers&>()))> {
        using Result = decltype(task(std::declval<Renderers&>()));
        auto packaged = std::make_shared<std::packaged_task<Result(Renderers&)>>(std::move(task));
        std::future<Result> result = packaged->get_future();
        post([packaged](Renderers& r) { (*packaged)(r); }, false);
        return result;
    }

    // Called on the render thread after each finished image (the editor wakes its event loop with it).
    void setOnImage(std::function<void()> onImage) {
        std::lock_guard lock(m_mutex);
        m_onImage = std::move(onImage);
    }

  private:
    void post(std::function<void(Renderers&)> task, bool reportErrors);
    void loop(std::promise<std::string> started);
    // A frame of `which` renderer: false when a newer request superseded it.
    // The levels a request draws, in order (0: the full frame).
    std::vector<int> levelsToDraw(const ViewRequest& request, int levels) const;
    bool renderLevel(Renderers& r, int level, uint64_t id, const ViewRequest& request, bool refinement, bool last);
    // The request's slab frame, after its full frame of sheets (ViewRequest::slabs).
    void renderSlabs(Renderers& r, uint64_t id, const ViewRequest& request);
    // Hands a finished image over and wakes the editor.
    void finish(RenderedView view);
    bool superseded(uint64_t id, std::chrono::steady_clock::time_point started, double budgetMs,
                    bool refinement) const;
    // Scenes to the renderers (setScenes); on failure the shown ones back, and the error rethrown.
    void uploadScenes(Renderers& r, const std::shared_ptr<const renderer::SplatScene>& full,
                      const Scenes& levels);
    // The scenes, gradients and LUTs shown before a change that failed with `failure`; should they not go
    // back either, a RenderError saying both.
    void restoreShown(Renderers& r, const std::string& failure);
    // The slab frames' scene: what the renderers hold (m_shown).
    void showSlabInputs(Renderers& r) const;
    // The message of a std::bad_alloc that nothing named on its way up, while `doing` something.
    std::string unnamedOutOfMemory(const char* doing) const;

    mutable std::mutex m_mutex;
    std::condition_variable m_wake, m_viewDone;
    std::deque<std::pair<std::function<void(Renderers&)>, bool>> m_tasks; // task, report its errors
    std::optional<std::pair<uint64_t, ViewRequest>> m_pendingView;
    uint64_t m_nextId = 1, m_newestId = 0, m_doneId = 0, m_inFlight = 0;
    std::optional<RenderedView> m_finished;
    std::deque<std::string> m_errors;
    std::string m_slabNote;
    renderer::FrameStats m_latestStats;
    bool m_stop = false;
    // Render thread only: each level's last time (0: not drawn since the scene changed) and last image
    // of the request under way, and their RMSE against the full frame that replaced them.
    std::array<double, kMaxViewLevels> m_levelMs{};
    std::array<double, kMaxViewLevels> m_levelRmse{-1, -1, -1, -1};
    std::array<std::vector<uint8_t>, kMaxViewLevels> m_levelPixels;
    uint64_t m_levelPixelsOf = 0;
    std::string m_sceneName; // the full scene's (its volume's) name, for messages
    // What the renderers hold, as last set: a scene change that fails puts it back.
    struct Shown {
        std::shared_ptr<const renderer::SplatScene> full, fullGradients;
        Scenes levels, levelGradients;
        std::optional<renderer::TfTables> fullLut;
        std::vector<renderer::TfTables> levelLuts;
    } m_shown;
    // Tests and benchmarks: every level of a view waits this long first, in steps a newer request
    // interrupts (SPLATLAB_RENDER_DELAY_MS), standing for a scan whose frames take that long.
    int m_delayMs = 0;
    std::function<void()> m_onImage;
    std::string m_glRenderer;
    std::thread m_thread; // last: started after every member it reads
};
