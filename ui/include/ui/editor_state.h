// What the editor's panels edit: plain data, no GL and no ImGui. The app owns one and hands it to the
// panels each frame; the renderer reads the camera and settings from it.
#pragma once
#include "renderer/oracle/footprint_inspection.h"
#include "renderer/math/camera.h"
#include "renderer/model/splat_settings.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/window.h"
#include "ui/file_browser.h"
#include "ui/gradient_opacity_curve.h"
#include "ui/tf2d_editor.h"
#include "ui/regime_tour.h"
#include "ui/save_notice.h"
#include "ui/split_view.h"
#include "ui/tf_editor.h"

#include <array>
#include <filesystem>
#include <optional>
#include <string>

namespace ui {

// How a 3D mouse's knob moves the camera (space_mouse.h).
struct SpaceMouseMapping {
    bool enabled = true;
    double speed = 1.0;              // multiplies every rate
    bool invertRotation = false;     // turn the camera, not the object
    bool invertTranslation = false;  // move the camera, not the object
};

// The Performance panel's load: re-render every UI frame, and turn the camera while doing so.
struct PerfSettings {
    bool renderContinuously = false;
    double spinDegPerS = 0.0;   // azimuth speed while rendering continuously (0: still)
    // The chart's window on the recorded renders (perf_chart.h): `shown` columns wide, its right edge
    // `newestOffset` renders before the newest (0: the newest at the right edge). Fractional, so that a
    // slow drag or a small zoom adds up.
    double shown = 240.0;
    double newestOffset = 0.0;
    std::optional<uint64_t> hoveredFrame; // the render under the pointer on the chart (set by the chart)
    std::string csvFile = "frames.csv";   // Export CSV's path (written atomically)
    std::string csvSaved;                 // what the last export wrote
};

// The frame budget and the preview level. The renderer runs on a thread of its own: after any edit, large
// volumes (kMinVoxels and more) whose full frame took longer than the budget last time show the preview
// level first (half resolution, 8 times fewer splats), then the full frame replaces it; a newer edit
// supersedes a frame in flight. While the window is dragged only the preview level is re-classified, and
// the full scene kSettleS after the last move.
struct PreviewSettings {
    static constexpr double kSettleS = 0.25;
    static constexpr size_t kMinVoxels = size_t(1) << 22;   // 4 M: smaller volumes render fast enough
    static constexpr size_t kMinMegaVoxels = kMinVoxels >> 20;   // for the text that names it
    bool whileMoving = true;           // progressive: the preview level first when the full frame is slow
    double budgetMs = 0.0;             // a first image within this; 0: the driver's (150 ms llvmpipe, 16 GPU)
    double defaultBudgetMs = 150.0;    // the driver's (set by the app)
    bool available = false;            // the volume shown is large enough to preview (set by the app)
    std::optional<double> lastInput;   // seconds (the app's clock) of the last moving input
    bool shown = false;                // the viewport shows a coarser level, finer ones to follow (set by the app)
    int shownLevel = 0;                // which: 1/2^shownLevel per axis (set by the app)
    bool farLevels = true;             // far views rest on the coarsest level whose kernels are under the
                                       // low-pass threshold (renderer/model/detail_levels.h)
    int farLevel = 0;                  // the level the view shown rests on (set by the app; 0: full)
    bool moving(double now) const { return lastInput && now - *lastInput < kSettleS; }
};

// Settings > Image-aligned slabs: a still view's full frame drawn again in slabs parallel to the image
// (renderer/oracle/image_slabs.h; pre- or post-classified, shaded as the view), which replaces the sheets'
// image once done. Seconds a frame on a CPU driver, so the sheets show while the view moves.
struct SlabView {
    bool enabled = false;
    double thickness = 0.5;        // voxel spacings (mean spacing): docs/accuracy.md's thickness curve
    bool postClassified = true;    // the TF applied to the reconstructed value, not to each voxel
    std::string status;            // the last slab frame's time, or why the sheets show (set by the app)
};
// What the slabs take, in the editor's ranges (the Settings panel's slider, sessions).
constexpr double kSlabThicknessLo = 0.1, kSlabThicknessHi = 4.0;

// A file dropped on the window, waiting for the panel whose button opens such a file (dropFile).
enum class FileAction { None, OpenVolume, OpenSession, LoadTransferFunction };

struct EditorState {
    renderer::Camera camera; // orbit camera; "Reset camera" restores renderer::Camera{}, keeping `up`
    renderer::SplatSettings settings;        // what every render of the viewport uses
    // The transfer function the scene is classified with; the Transfer function panel edits it.
    renderer::TransferFunction tf = renderer::builtinPreset("ct-skin-bone");
    bool tfEdited = false;             // points changed since the preset or file was loaded or saved
    int tfSelected = -1;               // the opacity point the panel edits; -1: none
    int tfColourSelected = -1;         // the colour stop the panel edits; -1: none (one of the two at most)
    float tfGrabDx = 0, tfGrabDy = 0;  // while dragging: point minus mouse at the press, pixels
    double tfShift = 0.0;              // the Shift field's offset (data units) during its drag; 0 between
    std::string tfFile = "transfer_function.json";   // the panel's Load / Save path
    bool tfLogOpacity = false;                       // the curve's opacity axis in decades (tf_editor.h)
    bool tfGalleryOpen = false;                      // the panel's Gallery open: the editor draws thumbnails
    GradientCurveEdit tfGradient;                    // the gradient opacity curve's selected point
    Tf2dEdit tf2d;                                   // the 2D section's selected widget and drag
    TfHistory tfHistory;                             // undo / redo, a step per gesture
    std::optional<renderer::TransferFunction> tfGestureStart;   // the TF before the gesture under way
    std::array<float, 3> background{0.055f, 0.060f, 0.075f}; // linear RGB behind the volume
    std::string errorMessage; // shown in a modal until dismissed; empty when none
    SaveNotice saveNotice;    // "Saved FILE" in the corner after any save, fading (save_notice.h)
    // The voxel the mouse points at in the viewport (renderer::probePixel) and its value in data units:
    // the viewport's tooltip shows it and the Transfer function panel marks the value on its axis. Empty
    // while the mouse is elsewhere, a button is down, or the pixel sees only air.
    struct ProbedVoxel {
        glm::ivec3 voxel{0};
        float value = 0.0f;
    };
    std::optional<ProbedVoxel> probe;
    // Settings > Inspect > Footprint inspector: the probed voxel's footprint, set by the app (footprint_inspector.h).
    bool inspectFootprint = false;
    std::optional<renderer::FootprintInspection> footprint;
    renderer::WindowSettings window; // which data values map onto the TF (custom: data units)
    bool histogramLog = true;        // the Window section's histogram: log-scale counts
    bool gradientsReady = false;     // the scene has gradients: shading and surface splats can be on
    bool showHeatmap = false;        // the viewport shows the filter-mode heatmap over the image
    double heatmapOpacity = 1.0;     // ...blended: 0 the image only, 1 the heatmap only
    int measureRepeats = 5;          // Filters > Measure: timed frames of each setting (median, p10, p90)
    SplitView split;                 // the viewport in panes, each with its own filter (split_view.h)
    SlabView slabs;                  // a still view refined with image-aligned slabs
    std::optional<RegimeTour> tour;  // the camera dollying near to far and back (Filters panel); none: still
    // Files: the volume shown (set by the app once it loaded), and the Files section's path fields.
    std::filesystem::path loadedVolume;
    std::filesystem::path openingVolume;   // being read on the worker (set by the app); empty when none
    std::string volumeFile;
    std::string sessionFile = "session.json";
    std::string imageFile = "view.png";   // Save image: PNG over the background, or EXR/TIFF float RGBA
    std::string imageSaved;               // what the last Save image wrote (set by the app)
    FileAction pendingFile = FileAction::None;   // a dropped file its panel opens when next drawn
    FileBrowserState fileBrowser;                // the Browse popup's folder and pick (file_browser.h)
    RecentFiles recentFiles;                     // per kind, newest first; kept in configDir between runs
    std::filesystem::path configDir; // where the editor keeps its settings; empty: nowhere (tests)
    SpaceMouseMapping spaceMouse;
    std::string spaceMouseStatus;    // the device found, or why there is none (set by the app)
    PerfSettings perf;
    PreviewSettings preview;
};

} // namespace ui
