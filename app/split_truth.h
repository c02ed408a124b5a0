// The split view's ground truth, for its |A - ground truth| pane (ui/split_view.h): the reference Measure
// and `splatlab report` compare with (renderer/oracle/ground_truth.h, cachedGroundTruth), computed on a
// worker thread below the UI's and the render's priority, coarse first (a quarter of the pane's size per
// axis, shown upsampled) and then at the pane's size. It takes seconds to minutes on a CPU driver, so a new
// view (a camera move, a TF edit, another pane size) supersedes the one under way: that worker is
// cancelled and whatever it had is dropped, so a truth is only ever handed out for the view it is of.
#pragma once
#include "renderer/io/image.h"
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/splat_settings.h"

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

class SplitTruth {
  public:
    using Clock = std::chrono::steady_clock;
    // `cacheDir` empty: never cached. A wanted view starts once it has stayed the same for `rest` (a drag
    // asks for a new view every frame: only the view it rests at is worth the cores). `lowPriority`: its
    // threads below the render thread's (an editor's UI stays fluid; a scripted run that waits for it
    // does not lower it, or other load would starve it).
    SplitTruth(std::filesystem::path cacheDir, Clock::duration rest, bool lowPriority = true);
    ~SplitTruth(); // cancels and joins every worker
    SplitTruth(const SplitTruth&) = delete;
    SplitTruth& operator=(const SplitTruth&) = delete;

    // What a truth is of: the plane, the settings the truth depends on and the scene's version, in a
    // string (equal strings: the same truth).
    static std::string viewKey(const renderer::ImagePlane& plane, const renderer::SplatSettings& settings,
                               uint64_t sceneVersion);

    // The view the difference pane is of now, asked each frame. The same key as last time: nothing
    // changes. Another: the truth under way is cancelled and what was computed is dropped; the new view
    // starts after the rest (scene() is called then, for the copy the worker reads).
    void want(const std::string& key, const renderer::ImagePlane& plane,
              const renderer::SplatSettings& settings,
              const std::function<std::shared_ptr<const renderer::SplatScene>()>& scene);
    void clear(); // no truth wanted: the one under way cancelled (its thread ends on its own, unjoined)

    // The finest truth finished for the view wanted, at the pane's size (a coarse one upsampled).
    struct Truth {
        std::string key;
        std::shared_ptr<const renderer::Image> image; // at the pane's size
        bool coarse = false;
        int computedWidth = 0, computedHeight = 0; // the resolution it was computed at
        double seconds = 0.0;                      // from the view's start to this truth
        bool cached = false;                       // read from the cache, not computed
    };
    std::optional<Truth> latest() const;
    bool computing() const;                   // wanted and not yet at full size (nor failed)
    bool coarseComputing() const;             // still on the coarse one (or resting before it)
    std::optional<std::string> error() const; // why the wanted view's truth failed
    void waitUntilDone();                     // scripted runs: starts the wanted view now, and waits

  private:
    struct Job;
    void startPending(bool now);
    void reap(); // joins the cancelled workers that have ended

    std::filesystem::path m_cacheDir;
    Clock::duration m_rest;
    // Tests: every truth waits this long first, in steps a newer view interrupts (SPLATLAB_TRUTH_DELAY_MS),
    // standing for a scan whose truth takes minutes.
    int m_delayMs = 0;
    bool m_lowPriority = true;
    std::string m_wantedKey;
    renderer::ImagePlane m_plane;
    renderer::SplatSettings m_settings;
    std::function<std::shared_ptr<const renderer::SplatScene>()> m_scene;
    Clock::time_point m_wantedSince;
    std::shared_ptr<Job> m_job;                  // of m_wantedKey, once started
    std::vector<std::shared_ptr<Job>> m_retired; // cancelled, their threads still ending
};
