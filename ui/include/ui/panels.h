// The editor's panels: each draws into the current ImGui window and edits EditorState; none owns GL
// objects. applyOrbitInput() is the pure camera rule behind the viewport's mouse handling.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/oracle/filter_comparison.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/model/volume.h"
#include "ui/editor_state.h"
#include "ui/heatmap_legend.h"
#include "ui/perf_history.h"
#include "ui/speed_error_chart.h"

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ui {

// == Settings

struct SettingsChanges {
    bool settingsChanged = false; // a SplatSettings field changed
    bool cameraChanged = false;   // field of view, up axis or "Reset camera"
    bool openVolume = false;      // "Open" beside the volume's path: the app loads state.volumeFile
    std::string openScene;        // a demo scene picked: the app opens it in its TF and view
    // A session was opened into the state: the app loads sessionVolume (when it is not the volume shown)
    // or re-classifies the one it has with the session's window and transfer function.
    bool sessionOpened = false;
    std::filesystem::path sessionVolume;
    bool saveImage = false;       // "Save image": the app writes the view shown to state.imageFile
    bool frame = false;           // "Frame": the app moves the camera to renderer::framedCamera()
    bool any() const { return settingsChanged || cameraChanged; }
};

// Files (open a volume or a demo scene, with what to look for in it; open and save sessions; save the
// view as an image), kernel scale, cutoff, density, filter mode,
// compositing, shading, heatmap, field of view, up axis, camera reset, 3D mouse. Session files that
// fail to open or save set state.errorMessage and change nothing else.
SettingsChanges drawSettingsPanel(EditorState& state);

// A file dropped on the editor's window: a session (JSON with "splatlab_session"), a transfer function
// (other JSON) or a volume (anything else). Puts its path in that panel's field and marks the panel's
// button as pressed (state.pendingFile), so it opens exactly as the button would, errors included.
// Returns the title of the panel to bring to the front (the button acts when its panel is drawn).
const char* dropFile(EditorState& state, const std::filesystem::path& file);

// == Transfer function

// A preset's thumbnail in the Transfer function panel's gallery, drawn on the volume shown.
struct GalleryThumbnail {
    std::string name;     // a builtinPresetNames() name
    unsigned texture = 0; // the UI's GL texture, kThumbnailPx square; 0: not drawn yet
};

struct TransferFunctionView {
    const renderer::Histogram* histogram = nullptr; // of the whole volume, drawn behind the curve; null: none
    renderer::ValueRange window;                    // the data values the canvas spans (the scene's window)
    // Rescale's targets (data units); an empty range (lo == hi) disables its button.
    renderer::ValueRange dataRange;                 // the volume's min..max
    renderer::ValueRange percentile;                // p1..p99
    renderer::ValueRange visible;                   // the values of the voxels drawn now (visibleValueRange)
    GradientCurveView gradients{};                  // the gradient opacity curve's axis and histogram
    // The 2D section's histogram (valueGradientHistogram) and the values it spans; its axes are `window`
    // and gradients.maxMagnitude.
    const std::vector<uint32_t>* histogram2d = nullptr;
    renderer::ValueRange histogram2dWindow{};
    // False while a volume loads or the scene is re-classified: a TF in window fractions waits for the
    // window it will be shown with before it is fixed in data units.
    bool windowSettled = true;
    std::vector<GalleryThumbnail> gallery{}; // every preset, in builtinPresetNames() order; empty: none
};

// Preset; the opacity curve over the histogram (drag a point to move it, click empty space to add one,
// right-click a point to remove it) and under it the colour bar with its stops (the same gestures, across
// only); the selected point's value in data units and its opacity or colour; Shift and Rescale of the
// whole TF; Load and Save of TF files (JSON, written atomically); on the Undo row the Gallery button
// (state.tfGalleryOpen: view.gallery's thumbnails under the panel; a click on one applies that preset as
// the Preset combo would) and the collapsible gradient opacity curve (gradient_opacity_curve.h). A TF in
// window fractions (a built-in preset, a version-1 file) is fixed in data units over view.window when the
// panel first shows it. A file that fails to load or save sets state.errorMessage. Returns whether
// state.tf changed: the app then re-bakes the LUT, which is all a TF edit uploads.
bool drawTransferFunctionPanel(EditorState& state, const TransferFunctionView& view);
// The colour (ImGui's packed ABGR) of the line the panel draws at EditorState::probe's value.
constexpr unsigned kProbeMarkerColour = 0xFF33D6FFu;

// == Window and histogram

struct WindowView {
    const renderer::Volume* volume = nullptr;       // null: the section says there is no volume
    const renderer::Histogram* histogram = nullptr; // of the whole volume over its range
    renderer::ValueRange percentile;                // p1..p99, computed once per volume by the app
    renderer::ValueRange window;                    // the window the scene uses now
};

// Window mode (data range, percentile 1-99, custom lo..hi in data units) and the volume's histogram
// (log-scale toggle) with the window marked; the value range and count under the mouse are shown in
// the data's own units. Returns whether state.window changed (the app then re-classifies the scene).
bool drawWindowSection(EditorState& state, const WindowView& view);

// A modal with a progress bar and a Cancel button, for work running on another thread. Call it every
// frame (it never blocks): while `running` it is shown with `fraction` (0..1); the first frame after,
// it closes. Returns true on the frame Cancel is pressed.
bool drawProgressModal(const char* title, const std::string& text, double fraction, bool running);

// == Viewport

// Mouse motion over the viewport during one frame, in display pixels (x right, y down).
struct OrbitInput {
    float rotateDxPx = 0, rotateDyPx = 0; // left-button drag
    float panDxPx = 0, panDyPx = 0;       // right- or middle-button drag
    float wheelNotches = 0;               // positive = wheel turned away from the user = zoom in
};

constexpr double kOrbitDegPerPx = 0.3; // a 300 px drag turns the camera 90 degrees
constexpr double kZoomPerNotch = 0.9;  // distance multiplier per notch of zoom in (1/0.9 out)
constexpr double kMinDistance = 1.05;  // in bounding radii: just outside the volume's sphere
constexpr double kMaxDistance = 20.0;
constexpr double kMaxElevationDeg = 89.0; // short of the poles, where the azimuth degenerates

// Drag right: azimuth decreases (the volume turns right). Drag down: elevation increases. Pan moves the
// orbit centre with the mouse. Azimuth wraps to [-180, 180); elevation and distance clamp to the
// limits above. Returns whether the camera changed.
bool applyOrbitInput(renderer::Camera& camera, const OrbitInput& input);

struct ViewportResult {
    int widthPx = 0, heightPx = 0; // framebuffer pixels the panel shows: render at this size
    bool cameraChanged = false;
    bool frame = false;            // a left double-click: frame the view, as Settings > Camera > Frame
    // The mouse over the panel with no button down, in those pixels (x right, y down, as ImagePlane): where
    // the app probes for the voxel shown (EditorState::probe).
    std::optional<glm::dvec2> hoverPx;
};

// The difference pane's figures (ui::DifferencePane without its pixels).
struct ViewportDifference {
    double rmse = 0.0, psnrDb = 0.0; // renderer::compareImages of the two panes
    double scaleMax = 0.0;           // the error at the top of the colour scale
};

// One pane of the split view: its image (GL name; 0: none yet) and what it shows.
struct ViewportPane {
    unsigned texture = 0;
    std::string label;                            // "reconstruction, sheet-front-to-back"
    std::optional<ViewportDifference> difference; // the difference pane's figures
    std::string note;                             // instead of an image: why there is none (yet)
    bool isDifference = false;                    // the difference pane (splitLayout places it)
};

// What the viewport draws over the image while state.showHeatmap is on, or instead of it in a split view.
struct ViewportOverlay {
    unsigned heatmapTexture = 0;          // the filter-mode heatmap of the same render (GL name); 0: none
    std::optional<HeatmapLegend> legend;  // of the view shown; none: no legend (no volume)
    // The split view's panes, A first, the difference pane last (splitLayout); empty: the one image.
    std::vector<ViewportPane> panes;
};

// Shows `texture` (a GL texture name, 0 for none) stretched over the panel's whole content region;
// mouse drags and the wheel inside it move state.camera. With the heatmap on, the heatmap is drawn over
// the image with alpha state.heatmapOpacity (GL's blend: heatmap x opacity + image x (1 - opacity); at
// 0 the image alone, at 1 the heatmap alone) and the legend in the bottom-left corner.
ViewportResult drawViewportPanel(EditorState& state, unsigned texture, const ViewportOverlay& overlay = {});

// == Filters

struct FiltersView {
    const renderer::ImagePlane* plane = nullptr;   // the view of the last render; null: no volume
    glm::ivec3 dims{0};                            // the volume's grid
    glm::dvec3 origin{0.0}, spacing{1.0};
    double radius = 1.0;                           // bounding radius: depths are shown in it
    renderer::FrameStats frame;                    // the last render (per-filter splats with counters)
    std::optional<std::array<uint64_t, 3>> patches;   // patches per filter the adaptive classifier
                                                      // gives this view (renderer's patchModes)
    // Cost beside error (renderer/filter_comparison.h): the filters measured so far, whether a
    // measurement is under way (ground-truth progress 0..1) and whether the view changed since.
    std::vector<renderer::FilterMeasurement> measurements;
    int cropPx = 0;                 // side of the centre crop the errors are taken over
    bool measuring = false, measurementsStale = false;
    double truthProgress = 0.0;
    size_t settingsToMeasure = 0;   // > 0 once the ground truth is in: the bar counts the settings timed
    bool slabsInForce = false;      // the still view ends in image-aligned slabs (Settings): their point is ringed
};

struct FiltersChanges {
    bool settingsChanged = false;   // the heatmap toggle (also turned on by the regime tour)
    bool measure = false;           // "Measure": time each filter and take its error in this view
    bool cancel = false;            // stop the measurement under way
    std::optional<SpeedErrorChart> chart;   // the speed-against-error chart as drawn this frame, if any
};

// Which filter each part of the view takes, why, and at what cost: the heatmap toggle, its opacity
// over the image and the regime tour (state.tour, see regime_tour.h), the filter in
// force, the shares of patches (and of splats, with GPU counters) per filter; a depth axis from the
// eye coloured by the filter a kernel takes there, with the volume's depths over it; and, measured on
// request, each filter's frame time beside its error against the ground truth.
FiltersChanges drawFiltersPanel(EditorState& state, const FiltersView& view);

// == Stats and help

struct StatsView {
    renderer::FrameStats frame;               // of the last render
    const renderer::Volume* volume = nullptr; // null when no volume is loaded
    size_t visibleSplats = 0;                 // voxels the TF leaves visible
    uint64_t sceneBytes = 0;                  // GPU memory of the scene (SplatRenderer::sceneBytes)...
    size_t sceneVoxels = 0;                   // ...of this many voxels (0: the volume's; a level has fewer)
    uint64_t workingBytes = 0;                // ...and of the tiled passes' buffers (workingBytes)
    std::string glRenderer;                   // GL_RENDERER of the renderer's context
    std::string levels;                       // the levels of detail: on screen, times, errors ("": none)
};
void drawStatsPanel(const StatsView& stats);

// == Performance
// Live timings of recent renders: the GPU time of each, split by pass (stacked, one colour a pass),
// with its CPU time over it; medians, p95 and extremes; renders a second when rendering continuously.
// "Render continuously" and "Spin" give a steady load to watch; "Clear" empties `history`; "Copy" puts
// summaryText(context(): what is rendered, where, asked for only then) on the clipboard.
void drawPerformancePanel(EditorState& state, PerfHistory& history,
                          const std::function<std::string()>& context = [] { return std::string(); });

void drawHelpPanel();

// Opens a modal with state.errorMessage while it is non-empty; "OK" clears it.
void drawErrorModal(EditorState& state);

} // namespace ui
