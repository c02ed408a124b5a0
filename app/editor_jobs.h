// Work the editor hands to worker threads and polls each frame: reading a volume, its gradients, and the
// Filters panel's ground truth. The UI thread joins each job and takes its result; nothing here draws.
#pragma once
#include "editor_document.h"

#include "renderer/errors.h"
#include "renderer/io/volume_io.h"
#include "renderer/math/shading.h"
#include "renderer/oracle/demo_scenes.h"
#include "renderer/model/gradients.h"
#include "renderer/model/post_classification.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/window.h"
#include "renderer/oracle/filter_comparison.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/speed_error.h"
#include "renderer/out_of_memory.h"
#include "ui/editor_state.h"

#include <array>
#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

// Work on a worker thread that the UI thread polls each frame: its progress (0..1), a cancel flag the
// work's progress callback returns, and, once `done`, its result or the message of what it threw.
// Destroying the job cancels and joins it, so it must go before anything the work reads. The work names
// what it allocates (renderer::namingAllocation); a std::bad_alloc it did not name still becomes a
// message naming `subject`.
template <class T> struct WorkerJob {
    std::thread thread;
    std::atomic<double> fraction{0.0};
    std::atomic<bool> cancel{false}, done{false};
    std::optional<T> result; // written before `done`; empty when cancelled or failed
    std::string error;       // an exception from the worker, if any
    std::string subject =
        "a worker thread"; // whose work it is, in the message of an allocation it did not name

    // `work(progress)` returns the result (or an optional of it); `progress(f)` returns false once cancelled.
    template <class Work> void start(Work work) {
        thread = std::thread([this, subject = subject, work] {
            try {
                result = work([this](double f) {
                    fraction = f;
                    return !cancel.load();
                });
            } catch (const std::bad_alloc&) {
                result.reset();
                error = subject + ": out of memory (in a step that does not name its allocations)";
            } catch (const std::exception& e) {
                result.reset();
                error = e.what();
            }
            done = true;
        });
    }
    ~WorkerJob() {
        cancel = true;
        if (thread.joinable()) thread.join();
    }
};

// Gradients computed after a volume loads, the full volume's and each level's, packed as the scenes keep
// them, with a copy of each for the render thread (a scene of name, dims and gradients: all its
// SplatRenderer::setGradients reads), so the UI thread only moves them; the UI shows the progress modal
// meanwhile (the levels take the last few percent).
struct Gradients {
    renderer::GradientField field;
    renderer::PackedGradients packed;
    std::vector<uint64_t> magnitudeCounts;   // the full volume's voxels per magnitude byte
    std::vector<std::optional<renderer::GradientField>> levelFields;
    std::vector<renderer::PackedGradients> levelPacked;
    std::shared_ptr<const renderer::SplatScene> forRender;
    std::vector<std::shared_ptr<const renderer::SplatScene>> levelsForRender;
};
struct GradientJob : WorkerJob<Gradients> {
    GradientJob(const renderer::Volume& volume, std::vector<const renderer::Volume*> levels) {
        subject = renderer::volumeSubject(volume.name);
        start([&volume, levels](const renderer::ProgressCallback& progress) -> std::optional<Gradients> {
            // Each step's allocation named with its size: the field (3 int16 a voxel), the packed copy and
            // the render thread's copy of it (4 bytes a voxel each).
            const auto named = [](const renderer::Volume& v, const char* what, uint64_t bytesPerVoxel,
                                  auto step) {
                return renderer::namingAllocation(renderer::volumeSubject(v.name), what,
                                                  v.voxelCount() * bytesPerVoxel, "", step);
            };
            const auto forRender = [&](const renderer::Volume& v, const renderer::PackedGradients& packed) {
                return named(v, "copy of its gradients for the renderer", 4, [&] {
                    auto scene = std::make_shared<renderer::SplatScene>();
                    scene->name = v.name, scene->dims = v.dims, scene->gradients = packed.texels;
                    return std::shared_ptr<const renderer::SplatScene>(std::move(scene));
                });
            };
            const auto packed = [&](const renderer::Volume& v,
                                    const std::optional<renderer::GradientField>& f) {
                return named(v, "packed gradients", 4, [&] {
                    return f ? renderer::packGradients(*f) : renderer::PackedGradients{};
                });
            };
            std::optional<renderer::GradientField> field = named(volume, "gradients", 6, [&] {
                return renderer::computeGradients(volume, [&](double f) { return progress(0.9 * f); });
            });
            if (!field) return std::nullopt;
            Gradients out;
            out.packed = packed(volume, field);
            out.forRender = forRender(volume, out.packed);
            out.magnitudeCounts = renderer::magnitudeHistogram(out.packed.texels);
            out.field = std::move(*field);
            for (const renderer::Volume* level : levels) {
                out.levelFields.push_back(
                    named(*level, "gradients", 6, [&] { return renderer::computeGradients(*level); }));
                out.levelPacked.push_back(packed(*level, out.levelFields.back()));
                out.levelsForRender.push_back(forRender(*level, out.levelPacked.back()));
                if (!progress(0.95)) return std::nullopt;
            }
            return out;
        });
    }
};

// A volume read on the worker: what the UI thread needs to show it (it makes the GL parts), with copies
// of the scenes for the render thread made there too.
struct LoadedVolume {
    renderer::Volume volume;
    renderer::Histogram histogram;   // of the whole volume, for the Window section
    renderer::ValueRange percentile; // p1..p99
    renderer::SplatScene scene;      // classified with the job's TF over its window
    std::unique_ptr<Preview> preview; // its levels, classified alike (volumes of kMinVoxels or more)
    std::shared_ptr<const renderer::SplatScene> sceneForRender;
    std::vector<std::shared_ptr<const renderer::SplatScene>> levelsForRender;
};

// Opening a volume: read, aligned to its world axes, its histogram taken, its scene classified and its
// levels built on the worker, since a large scan takes seconds; the UI shows the progress modal
// meanwhile. Cancel stops the reading at once (volume_io.h), the rest between steps. The work holds its
// own copies: the job's members are gone before the base joins the thread.
struct VolumeJob : WorkerJob<LoadedVolume> {
    std::filesystem::path path;
    renderer::TransferFunction tf;
    VolumeJob(const std::filesystem::path& file, const std::optional<renderer::RawOptions>& raw,
              const renderer::TransferFunction& classify, const renderer::WindowSettings& window)
        : path(file), tf(classify) {
        subject = file.string();
        start([file, raw, classify,
               window](const renderer::ProgressCallback& progress) -> std::optional<LoadedVolume> {
            LoadedVolume out;
            try {
                out.volume = renderer::loadVolumeOrScene(file, raw, [&](double f) { return progress(0.6 * f); });
            } catch (const renderer::Cancelled&) {
                return std::nullopt;
            }
            if (!progress(0.6)) return std::nullopt;
            // The percentiles sort a copy of the voxels (4 bytes each).
            const auto named = [&](const char* what, uint64_t bytes, auto step) {
                return renderer::namingAllocation(file.string(), what, bytes, "", step);
            };
            named("copy of the voxels for the p1-p99 window", out.volume.voxelCount() * 4, [&] {
                out.histogram = renderer::computeHistogram(out.volume, 128);
                out.percentile = renderer::percentileWindow(out.volume, 1.0, 99.0);
            });
            if (!progress(0.7)) return std::nullopt;
            out.scene =
                renderer::buildSplatScene(out.volume, classify, renderer::windowFor(out.volume, window));
            out.sceneForRender = copyForRender(out.scene);
            if (!progress(0.9)) return std::nullopt;
            if (out.volume.voxelCount() >= ui::PreviewSettings::kMinVoxels) {
                // The levels at 1/2, 1/4 and 1/8 per axis: a seventh of the voxels' floats.
                out.preview = named("preview levels", out.volume.voxelCount() * 4 / 7,
                                    [&] { return std::make_unique<Preview>(out.volume); });
                out.preview->classify(classify, out.scene.window);
                for (const Level& level : out.preview->levels)
                    out.levelsForRender.push_back(copyForRender(level.scene));
            }
            progress(1.0);
            return out;
        });
    }
};

// Re-classifying over a new window on the worker: every voxel, or (while the window is dragged) the
// levels' only. It reads the document's volume, levels and gradients, so the loop takes no gradients
// while one runs and drops it before the document goes.
struct Classified {
    bool levelsOnly = false;
    renderer::SplatScene full;        // empty when levelsOnly
    std::vector<renderer::SplatScene> levels;
    std::shared_ptr<const renderer::SplatScene> fullForRender;
    std::vector<std::shared_ptr<const renderer::SplatScene>> levelsForRender;
};
struct ClassifyJob : WorkerJob<Classified> {
    ClassifyJob(const Document& doc, const renderer::TransferFunction& tf, renderer::ValueRange window,
                bool levelsOnly) {
        subject = renderer::volumeSubject(doc.scene.name);
        start([&doc, tf, window, levelsOnly](const renderer::ProgressCallback&) -> std::optional<Classified> {
            Classified out;
            out.levelsOnly = levelsOnly;
            if (!levelsOnly) {
                out.full = classifiedScene(*doc.volume, tf, window, doc.gradients);
                out.fullForRender = copyForRender(out.full);
            }
            if (doc.preview)
                for (const Level& level : doc.preview->levels) {
                    out.levels.push_back(classifiedScene(level.volume, tf, window, level.gradients));
                    out.levelsForRender.push_back(copyForRender(out.levels.back()));
                }
            return out;
        });
    }
};

// The Filters panel's "Measure": the ground truths of the view's centre crop on the worker (cached on
// disk), then, one setting a UI frame, each filter x compositing mode (speed_error.h) timed on the whole
// view `repeats` times and compared on the crop; where the still view ends in image-aligned slabs, those
// slabs last (against the post-classified truth where they post-classify).
// It works on a copy of the scene: a TF edit changes the document's while the worker reads.
struct FilterComparisonJob {
    renderer::SplatScene scene;
    renderer::ImagePlane view, crop;
    renderer::SplatSettings settings;
    std::vector<renderer::SplatSettings> toMeasure; // speedErrorSettings(settings)
    std::optional<renderer::SlabOptions> slabs;     // the slabs in force, measured after toMeasure
    size_t measured = 0;                            // of toMeasure, then the slabs, measured so far
    // Set as the job ends (a cancel, any edit of the view): a slab frame being timed stops (seconds each on
    // llvmpipe) instead of holding the render thread.
    std::shared_ptr<std::atomic<bool>> ended = std::make_shared<std::atomic<bool>>(false);
    WorkerJob<renderer::CropTruths> truth;          // last: destroyed (joined) before the scene it reads

    FilterComparisonJob(const renderer::SplatScene& s, const renderer::ImagePlane& v,
                        const renderer::SplatSettings& set, std::optional<renderer::SlabOptions> slabsInForce)
        : scene(s), view(v), crop(renderer::centreCrop(v, renderer::kComparisonCropPx)), settings(set),
          toMeasure(renderer::speedErrorSettings(set)), slabs(slabsInForce) {
        // Slabs that refuse to post-classify this scene (gradient opacity, a 2D TF) draw no frame to time,
        // and their truth would fail the whole measurement: the sheets alone, as the view shows them.
        if (slabs && slabs->postClassified) {
            try {
                renderer::requirePostClassifiable(scene, settings, "image-aligned slabs");
            } catch (const renderer::RenderError&) {
                slabs.reset();
            }
        }
        truth.subject = renderer::volumeSubject(s.name) + "'s ground truth";
        truth.start([this](const renderer::ProgressCallback& progress) {
            return renderer::cropTruths(scene, crop, settings, {}, renderer::defaultGroundTruthCacheDir(), progress,
                                        slabs && slabs->postClassified);
        });
    }
    ~FilterComparisonJob() { *ended = true; }
    size_t settingsToMeasure() const { return toMeasure.size() + (slabs ? 1 : 0); }
};
