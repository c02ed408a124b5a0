// ui layer: the dock layout math and the orbit rule as pure functions, then the panels and the dock
// space driven through ImGui with no renderer backend (mouse events in, settings structs out; no pixels).
#include "imgui_null.h"
#include "ui/dock_layout.h"
#include "ui/panels.h"
#include "ui/perf_history.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h> // ImGuiContext::HoveredId and FindWindowByName, to find widgets to click

#include <functional>
#include <vector>
#include <map>

namespace {

using ui::DockLayout;
using ui::Rect;

float area(const Rect& r) { return r.w * r.h; }

bool overlaps(const Rect& a, const Rect& b) {
    return a.x < b.right() && b.x < a.right() && a.y < b.bottom() && b.y < a.bottom();
}

// The pieces that must tile the window: every leaf and every splitter bar.
std::vector<Rect> tiles(const DockLayout& layout, const ui::DockRects& rects) {
    std::vector<Rect> out;
    for (size_t i = 0; i < layout.nodes.size(); ++i)
        out.push_back(layout.nodes[i].isLeaf() ? rects.node[i] : rects.splitter[i]);
    return out;
}

float extent(const DockLayout& layout, const ui::DockRects& rects, const char* region, bool width) {
    const Rect& r = rects.node[layout.find(region)];
    return width ? r.w : r.h;
}

} // namespace

// == Dock layout math

TEST(DockLayout, LeavesAndSplittersTileTheWindowWithoutGapsOrOverlaps) {
    const DockLayout layout = ui::makeEditorLayout();
    for (Rect window : {Rect{0, 0, 1280, 800}, Rect{0, 0, 1920, 1080}, Rect{10, 20, 641, 479},
                        Rect{0, 0, 300, 200}, Rect{0, 0, 3, 2}}) {
        SCOPED_TRACE(testing::Message() << window.w << "x" << window.h);
        const std::vector<Rect> pieces = tiles(layout, ui::computeDockRects(layout, window));
        float covered = 0;
        for (size_t i = 0; i < pieces.size(); ++i) {
            const Rect& p = pieces[i];
            EXPECT_GE(p.w, 0);
            EXPECT_GE(p.h, 0);
            EXPECT_GE(p.x, window.x);
            EXPECT_GE(p.y, window.y);
            EXPECT_LE(p.right(), window.right());
            EXPECT_LE(p.bottom(), window.bottom());
            covered += area(p);
            for (size_t j = i + 1; j < pieces.size(); ++j)
                EXPECT_FALSE(overlaps(p, pieces[j])) << i << " vs " << j;
        }
        // Inside the window and pairwise disjoint, so equal total area means no gaps.
        EXPECT_FLOAT_EQ(covered, area(window));
    }
}

TEST(DockLayout, EditorLayoutPlacesLeftColumnViewportAndBottomStrip) {
    const DockLayout layout = ui::makeEditorLayout();
    const ui::DockRects rects = ui::computeDockRects(layout, {0, 0, 1280, 800});
    const Rect left = rects.node[layout.find("left")];
    const Rect viewport = rects.node[layout.find("viewport")];
    const Rect bottom = rects.node[layout.find("bottom")];
    EXPECT_EQ(left.x, 0);
    EXPECT_EQ(left.h, 800); // the left column runs the full height
    EXPECT_EQ(viewport.x, left.right() + layout.splitterPx);
    EXPECT_EQ(viewport.w, bottom.w); // the bottom strip sits under the viewport only
    EXPECT_EQ(bottom.bottom(), 800);
    EXPECT_EQ(left.w, std::round(0.25f * (1280 - layout.splitterPx)));
    EXPECT_EQ(layout.find("nowhere"), -1);
}

TEST(DockLayout, SplitterDragsStopAtMinSizes) {
    DockLayout layout = ui::makeEditorLayout();
    ui::DockNode& root = layout.nodes[0];
    ui::DockNode& centre = layout.nodes[size_t(layout.find("centre"))];
    const Rect window{0, 0, 1280, 800};
    const float columnsAvail = window.w - layout.splitterPx;

    ui::setFirstExtentPx(root, 5.0f, columnsAvail); // drag the left column almost shut
    auto rects = ui::computeDockRects(layout, window);
    EXPECT_EQ(extent(layout, rects, "left", true), root.minFirstPx);

    ui::setFirstExtentPx(root, 5000.0f, columnsAvail); // and far past the right edge
    rects = ui::computeDockRects(layout, window);
    EXPECT_EQ(extent(layout, rects, "viewport", true), root.minSecondPx);

    const float rowsAvail = window.h - layout.splitterPx;
    ui::setFirstExtentPx(centre, 5000.0f, rowsAvail); // bottom strip dragged off the screen
    rects = ui::computeDockRects(layout, window);
    EXPECT_EQ(extent(layout, rects, "bottom", false), centre.minSecondPx);
    ui::setFirstExtentPx(centre, -50.0f, rowsAvail);
    rects = ui::computeDockRects(layout, window);
    EXPECT_EQ(extent(layout, rects, "viewport", false), centre.minFirstPx);
}

TEST(DockLayout, WindowResizeKeepsRatios) {
    DockLayout layout = ui::makeEditorLayout();
    ui::setFirstExtentPx(layout.nodes[0], 400.0f, 1280 - layout.splitterPx);
    const auto before = ui::computeDockRects(layout, {0, 0, 1280, 800});
    EXPECT_EQ(extent(layout, before, "left", true), 400.0f);

    // Larger: the left column keeps its share, to the rounding pixel.
    const auto larger = ui::computeDockRects(layout, {0, 0, 1920, 1200});
    EXPECT_NEAR(extent(layout, larger, "left", true) / (1920 - layout.splitterPx),
                400.0f / (1280 - layout.splitterPx), 0.5f / (1920 - layout.splitterPx));

    // Too small for the min sizes, then back: the clamped layout did not overwrite the ratios.
    const auto tiny = ui::computeDockRects(layout, {0, 0, 400, 200});
    EXPECT_EQ(extent(layout, tiny, "left", true), std::floor(394.0f * 220.0f / 540.0f)); // shared by mins
    const auto again = ui::computeDockRects(layout, {0, 0, 1280, 800});
    for (size_t i = 0; i < layout.nodes.size(); ++i) {
        EXPECT_EQ(again.node[i].x, before.node[i].x);
        EXPECT_EQ(again.node[i].w, before.node[i].w);
        EXPECT_EQ(again.node[i].h, before.node[i].h);
    }
}

// == Orbit rule

TEST(OrbitInput, HorizontalDragTurnsAzimuthByTheStatedGain) {
    renderer::Camera camera;
    camera.azimuthDeg = 30.0;
    EXPECT_TRUE(ui::applyOrbitInput(camera, {.rotateDxPx = 100.0f}));
    EXPECT_NEAR(camera.azimuthDeg, 30.0 - 100.0 * ui::kOrbitDegPerPx, 1e-9);
    EXPECT_EQ(camera.elevationDeg, renderer::Camera{}.elevationDeg);
}

TEST(OrbitInput, AzimuthWrapsIntoHalfOpenRange) {
    renderer::Camera camera;
    camera.azimuthDeg = 170.0;
    ui::applyOrbitInput(camera, {.rotateDxPx = -200.0f}); // +60 degrees at 0.3 degrees a pixel
    EXPECT_NEAR(camera.azimuthDeg, 170.0 + 200.0 * ui::kOrbitDegPerPx - 360.0, 1e-9);
}

TEST(OrbitInput, ElevationClampsShortOfThePoles) {
    renderer::Camera camera;
    ui::applyOrbitInput(camera, {.rotateDyPx = 1e5f});
    EXPECT_EQ(camera.elevationDeg, ui::kMaxElevationDeg);
    ui::applyOrbitInput(camera, {.rotateDyPx = -1e5f});
    EXPECT_EQ(camera.elevationDeg, -ui::kMaxElevationDeg);
    EXPECT_LT(ui::kMaxElevationDeg, 90.0);
}

TEST(OrbitInput, WheelZoomScalesDistanceAndClampsToRange) {
    renderer::Camera camera;
    const double start = camera.distance;
    ui::applyOrbitInput(camera, {.wheelNotches = 1.0f});
    EXPECT_NEAR(camera.distance, start * ui::kZoomPerNotch, 1e-12);
    ui::applyOrbitInput(camera, {.wheelNotches = 200.0f});
    EXPECT_EQ(camera.distance, ui::kMinDistance);
    ui::applyOrbitInput(camera, {.wheelNotches = -200.0f});
    EXPECT_EQ(camera.distance, ui::kMaxDistance);
}

TEST(OrbitInput, PanMovesOrbitCentreWithTheMouseAndNoInputChangesNothing) {
    renderer::Camera camera;
    EXPECT_FALSE(ui::applyOrbitInput(camera, {}));
    EXPECT_TRUE(ui::applyOrbitInput(camera, {.panDxPx = 12.0f, .panDyPx = -5.0f}));
    EXPECT_EQ(camera.panPx, glm::dvec2(12.0, -5.0));
    EXPECT_EQ(camera.azimuthDeg, renderer::Camera{}.azimuthDeg);
}

// == Panels and dock space through ImGui with no renderer backend

namespace {

void expectSameState(const ui::EditorState& a, const ui::EditorState& b) {
    EXPECT_EQ(a.tf.name, b.tf.name);
    EXPECT_EQ(a.tf.colours.size(), b.tf.colours.size());
    EXPECT_EQ(a.tf.opacities.size(), b.tf.opacities.size());
    EXPECT_EQ(a.settings.kernelScale, b.settings.kernelScale);
    EXPECT_EQ(a.settings.cutoffSigmas, b.settings.cutoffSigmas);
    EXPECT_EQ(a.settings.density, b.settings.density);
    EXPECT_EQ(a.settings.filter, b.settings.filter);
    EXPECT_EQ(a.settings.compositing, b.settings.compositing);
    EXPECT_EQ(a.camera.fovYDeg, b.camera.fovYDeg);
    EXPECT_EQ(a.camera.azimuthDeg, b.camera.azimuthDeg);
    EXPECT_EQ(a.camera.distance, b.camera.distance);
}

} // namespace

TEST_F(ImGuiNull, SettingsPanelLeavesStateAloneWithoutInput) {
    ui::EditorState state;
    const ui::EditorState before = state;
    for (int i = 0; i < 3; ++i) {
        mouse(900, 700, false); // outside the panel
        frame([&] { EXPECT_FALSE(ui::drawSettingsPanel(state).any()); });
    }
    expectSameState(state, before);
}

TEST_F(ImGuiNull, ClickingCompositingComboAndXrayItemSelectsXray) {
    ui::EditorState state;
    ui::SettingsChanges changes;
    ImGuiID comboId = 0;
    auto body = [&] {
        comboId = ImGui::GetID("Compositing");
        const ui::SettingsChanges c = ui::drawSettingsPanel(state);
        changes.settingsChanged |= c.settingsChanged;
        changes.cameraChanged |= c.cameraChanged;
    };
    frame(body); // lay the panel out once so the id is known

    // 1. Hover and click the combo: its popup opens.
    const float comboY = findItem(comboId, 40.0f, 0.0f, 700.0f, body);
    ASSERT_GE(comboY, 0.0f) << "the Compositing combo was never hovered";
    click(40.0f, comboY, body);
    const ImGuiWindow* popup = ImGui::FindWindowByName("##Combo_00");
    ASSERT_NE(popup, nullptr);
    ASSERT_TRUE(popup->Active) << "the combo's popup did not open";
    EXPECT_FALSE(changes.settingsChanged);

    // 2. Hover and click "xray" in the popup, which opens below the combo.
    const ImGuiID xrayId = ImHashStr("xray", 0, popup->ID);
    const float x = 40.0f;
    const float itemY = findItem(xrayId, x, comboY, comboY + 200.0f, body);
    ASSERT_GE(itemY, 0.0f) << "the xray item was never hovered";
    EXPECT_FALSE(changes.settingsChanged);
    click(x, itemY, body);

    EXPECT_EQ(state.settings.compositing, renderer::Compositing::XRay);
    EXPECT_TRUE(changes.settingsChanged);
    EXPECT_FALSE(changes.cameraChanged);
}

// The Settings panel's checkbox `label`: found by hovering down its column, then clicked.
class SettingsCheckbox : public ImGuiNull {
protected:
    // Tall enough that the Settings panel's every section fits without scrolling.
    void SetUp() override {
        ImGuiNull::SetUp();
        windowHeight = 1200.0f;
        ImGui::GetIO().DisplaySize = ImVec2(1280.0f, windowHeight);
    }
    // The checkbox's row in the panel, or a negative number when the panel does not show it.
    float find(ui::EditorState& state, const char* label) {
        ImGuiID id = 0;
        auto body = [&] {
            id = ImGui::GetID(label);   // inside the panel's window, as the checkbox takes it
            ui::drawSettingsPanel(state);
        };
        mouse(900.0f, 700.0f, false);
        frame(body);
        return findItem(id, 20.0f, 0.0f, windowHeight, body);
    }
    // Clicks it at row y; returns whether the panel reported a settings change.
    bool click(ui::EditorState& state, float y) {
        bool changed = false;
        ImGuiNull::click(20.0f, y, [&] { changed |= ui::drawSettingsPanel(state).settingsChanged; });
        return changed;
    }
};

TEST_F(SettingsCheckbox, TiledSplattingSwitchesSheetsBetweenTilesAndTheRasteriser) {
    ui::EditorState state;
    state.settings.compositing = renderer::Compositing::SheetFrontToBack;
    ASSERT_TRUE(renderer::tiledSplatting(state.settings)) << "sheets start tiled (auto)";
    const float y = find(state, "Tiled splatting");
    ASSERT_GE(y, 0.0f) << "no Tiled splatting checkbox for sheets";
    EXPECT_TRUE(click(state, y));
    EXPECT_EQ(state.settings.primitive, renderer::SplatSettings::Primitive::Raster);
    EXPECT_FALSE(renderer::tiledSplatting(state.settings));
    EXPECT_TRUE(click(state, y));
    EXPECT_TRUE(renderer::tiledSplatting(state.settings));
    // Splat-every-sample cannot be tiled: an explicit Tiles falls back to the automatic choice.
    state.settings.primitive = renderer::SplatSettings::Primitive::Tiles;
    state.settings.compositing = renderer::Compositing::SplatEverySample;
    EXPECT_LT(find(state, "Tiled splatting"), 0.0f);
    EXPECT_EQ(state.settings.primitive, renderer::SplatSettings::Primitive::Auto);
    EXPECT_FALSE(renderer::tiledSplatting(state.settings));
}

TEST_F(SettingsCheckbox, CullHiddenSplatsTurnsOcclusionCullingOffAndOnFrontToBackOnly) {
    ui::EditorState state;
    state.settings.compositing = renderer::Compositing::SheetFrontToBack;
    ASSERT_TRUE(state.settings.occlusionCulling);
    const float y = find(state, "Cull hidden splats");
    ASSERT_GE(y, 0.0f) << "no Cull hidden splats checkbox front to back";
    EXPECT_TRUE(click(state, y));
    EXPECT_FALSE(state.settings.occlusionCulling);
    EXPECT_TRUE(click(state, y));
    EXPECT_TRUE(state.settings.occlusionCulling);
    // Back to front nothing is culled, so the box is not offered.
    state.settings.compositing = renderer::Compositing::SheetBackToFront;
    EXPECT_LT(find(state, "Cull hidden splats"), 0.0f);
}

// Slabs when still: a click turns the slab frame on and off; X-ray, surface splats and the split view
// grey it out, and a click there changes nothing.
TEST_F(SettingsCheckbox, SlabsWhenStillTogglesAndIsGreyedOutWhereTheSlabsCannotDraw) {
    ui::EditorState state;
    const float y = find(state, "Slabs when still");
    ASSERT_GE(y, 0.0f) << "no Slabs when still checkbox";
    EXPECT_TRUE(click(state, y));
    EXPECT_TRUE(state.slabs.enabled);
    EXPECT_TRUE(click(state, y));
    EXPECT_FALSE(state.slabs.enabled);
    for (const auto& greyed : std::vector<std::function<void(ui::EditorState&)>>{
             [](ui::EditorState& s) { s.settings.compositing = renderer::Compositing::XRay; },
             [](ui::EditorState& s) { s.settings.surfaceFlatten = 4.0; },
             [](ui::EditorState& s) { s.split.enabled = true; }}) {
        ui::EditorState other;
        greyed(other);
        const float at = find(other, "Slabs when still");
        EXPECT_FALSE(click(other, at >= 0.0f ? at : y));
        EXPECT_FALSE(other.slabs.enabled);
    }
}

// The preview toggle acts only where the app found the volume large enough to preview.
TEST_F(SettingsCheckbox, PreviewWhileMovingIsOfferedOnlyForVolumesLargeEnoughToPreview) {
    ui::EditorState state;
    state.preview.available = true;
    const float y = find(state, "Preview level first");
    ASSERT_GE(y, 0.0f) << "no Preview level first checkbox";
    click(state, y);
    EXPECT_FALSE(state.preview.whileMoving);
    click(state, y);
    EXPECT_TRUE(state.preview.whileMoving);
    // A small volume: the box is greyed out and a click changes nothing.
    state.preview.available = false;
    click(state, y);
    EXPECT_TRUE(state.preview.whileMoving);
}

TEST_F(ImGuiNull, ResetCameraButtonRestoresTheDefaultCamera) {
    ui::EditorState state;
    // The Camera section is below the Files, Splatting, Shading and Inspect sections: a tall window.
    windowHeight = 1000.0f;
    ImGui::GetIO().DisplaySize = ImVec2(1280, 1100);
    state.camera.azimuthDeg = 123.0;
    state.camera.distance = 7.0;
    bool cameraChanged = false;
    ImGuiID buttonId = 0;
    auto body = [&] {
        buttonId = ImGui::GetID("Reset camera");
        cameraChanged |= ui::drawSettingsPanel(state).cameraChanged;
    };
    frame(body);
    const float y = findItem(buttonId, 30.0f, 0.0f, 1000.0f, body);
    ASSERT_GE(y, 0.0f);
    EXPECT_FALSE(cameraChanged);
    click(30.0f, y, body);
    EXPECT_TRUE(cameraChanged);
    EXPECT_EQ(state.camera.azimuthDeg, renderer::Camera{}.azimuthDeg);
    EXPECT_EQ(state.camera.distance, renderer::Camera{}.distance);
}

TEST_F(ImGuiNull, FrameButtonBesideResetAndADoubleClickInTheViewportAskTheAppToFrameTheView) {
    ui::EditorState state;
    // The Camera section is below the Files, Splatting, Shading and Inspect sections: a tall window.
    windowHeight = 1000.0f;
    ImGui::GetIO().DisplaySize = ImVec2(1280, 1100);
    ui::SettingsChanges changes;
    ImGuiID resetId = 0, frameId = 0;
    auto body = [&] {
        resetId = ImGui::GetID("Reset camera");
        frameId = ImGui::GetID("Frame");
        const ui::SettingsChanges c = ui::drawSettingsPanel(state);
        changes.frame |= c.frame;
        changes.cameraChanged |= c.cameraChanged;
    };
    frame(body);
    const float y = findItem(resetId, 30.0f, 0.0f, 1000.0f, body);
    ASSERT_GE(y, 0.0f);
    const float x = findItemInRow(frameId, y, body);
    ASSERT_GE(x, 0.0f) << "no Frame button beside Reset camera";
    EXPECT_FALSE(changes.frame);
    click(x, y, body);
    EXPECT_TRUE(changes.frame);
    EXPECT_FALSE(changes.cameraChanged) << "the app frames the camera: it knows the scene and the viewport";

    // In the viewport one click does nothing; a second within ImGui's double-click time frames.
    const renderer::Camera before = state.camera;
    bool framed = false;
    auto viewport = [&] { framed |= ui::drawViewportPanel(state, 0).frame; };
    mouse(200, 300, false);
    frame(viewport);
    click(200, 300, viewport);
    EXPECT_FALSE(framed);
    click(200, 300, viewport);
    EXPECT_TRUE(framed);
    EXPECT_EQ(state.camera.distance, before.distance);
    EXPECT_EQ(state.camera.azimuthDeg, before.azimuthDeg);
}

TEST_F(ImGuiNull, LeftDragInViewportOrbitsByTheStatedGain) {
    ui::EditorState state;
    const double azimuth = state.camera.azimuthDeg;
    ui::ViewportResult result;
    auto body = [&] { result = ui::drawViewportPanel(state, 0); };
    mouse(200, 300, false);
    frame(body);
    mouse(200, 300, true);
    frame(body);
    mouse(250, 300, true); // 50 px to the right while held
    frame(body);
    EXPECT_TRUE(result.cameraChanged);
    mouse(250, 300, false);
    frame(body);
    EXPECT_NEAR(state.camera.azimuthDeg, azimuth - 50.0 * ui::kOrbitDegPerPx, 1e-6);
    EXPECT_GT(result.widthPx, 300); // the panel's content region, in pixels
    EXPECT_GT(result.heightPx, 600);
}

TEST_F(ImGuiNull, HoveringTheViewportGivesThePixelToProbeAndTheProbedValueInATooltip) {
    ui::EditorState state;
    ui::ViewportResult result;
    ImVec2 origin;
    auto body = [&] {
        origin = ImGui::GetCursorScreenPos();
        result = ui::drawViewportPanel(state, 1);   // a texture: something is shown
    };
    auto tooltipShown = [] {
        const ImGuiWindow* tip = ImGui::FindWindowByName("##Tooltip_00");
        return tip && tip->Active;
    };
    mouse(200, 300, false);
    frame(body);
    frame(body);
    ASSERT_TRUE(result.hoverPx.has_value());
    EXPECT_EQ(*result.hoverPx, glm::dvec2(200.0 - origin.x, 300.0 - origin.y));   // render pixels, y down
    EXPECT_FALSE(tooltipShown()) << "nothing probed yet";
    state.probe = ui::EditorState::ProbedVoxel{{3, 4, 5}, 1234.0f};
    frame(body);
    EXPECT_TRUE(tooltipShown());
    mouse(200, 300, true);   // a drag orbits: no probe
    frame(body);
    EXPECT_FALSE(result.hoverPx.has_value());
    EXPECT_FALSE(tooltipShown());
    mouse(200, 300, false);
    frame(body);
    mouse(1000, 300, false);   // outside the panel
    frame(body);
    EXPECT_FALSE(result.hoverPx.has_value());
}

TEST_F(ImGuiNull, DockSpaceDrawsFrontTabsAndDraggingTheColumnSplitterMovesIt) {
    DockLayout layout = ui::makeEditorLayout();
    std::map<std::string, int> drawn;
    std::vector<ui::DockPanel> panels;
    for (auto [title, region] : {std::pair{"Settings", "left"}, std::pair{"Viewport", "viewport"},
                                 std::pair{"Stats", "bottom"}, std::pair{"Help", "bottom"}})
        panels.push_back({title, region, [&drawn, t = std::string(title)] { ++drawn[t]; }});
    auto body = [&] {
        ImGui::NewFrame();
        ui::drawDockSpace(layout, panels);
        ImGui::Render();
    };
    const Rect window{0, 0, 1280, 800};
    const Rect bar = ui::computeDockRects(layout, window).splitter[0];
    const float leftBefore = ui::computeDockRects(layout, window).node[size_t(layout.find("left"))].w;

    ImGui::GetIO().MousePos = ImVec2(bar.x + bar.w * 0.5f, 400.0f);
    body();
    body();
    EXPECT_EQ(drawn["Settings"], 2);
    EXPECT_EQ(drawn["Viewport"], 2);
    EXPECT_EQ(drawn["Stats"], 2); // the first tab of the bottom strip is the one shown
    EXPECT_EQ(drawn["Help"], 0);
    // The splitter gap belongs to the host window, the regions to their own windows (on top of it).
    ASSERT_NE(ImGui::GetCurrentContext()->HoveredWindow, nullptr);
    EXPECT_STREQ(ImGui::GetCurrentContext()->HoveredWindow->Name, "##dock_host");
    const Rect viewport = ui::computeDockRects(layout, window).node[size_t(layout.find("viewport"))];
    ImGui::GetIO().MousePos = ImVec2(viewport.x + viewport.w * 0.5f, viewport.y + viewport.h * 0.5f);
    body();
    ASSERT_NE(ImGui::GetCurrentContext()->HoveredWindow, nullptr);
    EXPECT_STREQ(ImGui::GetCurrentContext()->HoveredWindow->Name, "##dock_viewport");
    ImGui::GetIO().MousePos = ImVec2(bar.x + bar.w * 0.5f, 400.0f);
    body();

    ImGui::GetIO().MouseDown[0] = true;
    body();
    ImGui::GetIO().MousePos.x += 60.0f;
    body();
    ImGui::GetIO().MouseDown[0] = false;
    body();
    EXPECT_EQ(ui::computeDockRects(layout, window).node[size_t(layout.find("left"))].w, leftBefore + 60.0f);
}

// == Window section and the progress modal

TEST_F(ImGuiNull, WindowSectionPercentileRadioSelectsThePercentileWindow) {
    renderer::Volume volume;
    volume.dims = {4, 1, 1};
    volume.values = {-1000, 0, 40, 3000};
    renderer::updateRange(volume);
    const renderer::Histogram histogram = renderer::computeHistogram(volume, 8);
    ui::EditorState state;
    bool changed = false;
    ImGuiID dataId = 0, percentileId = 0;
    auto body = [&] {
        dataId = ImGui::GetID("data range");
        percentileId = ImGui::GetID("percentile 1-99");
        changed |= ui::drawWindowSection(state, {.volume = &volume, .histogram = &histogram,
                                                 .percentile = {-1000, 3000}, .window = volume.range});
    };
    frame(body);
    EXPECT_FALSE(changed);
    const float y = findItem(dataId, 20.0f, 0.0f, 700.0f, body);
    ASSERT_GE(y, 0.0f) << "the data range radio was never hovered";
    const float x = findItemInRow(percentileId, y, body);   // to its right on the same line
    ASSERT_GE(x, 0.0f) << "the percentile radio was never hovered";
    click(x, y, body);
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.window.mode, renderer::WindowMode::Percentile);
}

TEST_F(ImGuiNull, ProgressModalCancelButtonReportsOnceAndTheModalClosesWhenWorkEnds) {
    bool cancelled = false, running = true;
    auto body = [&] { cancelled |= ui::drawProgressModal("Working", "gradients", 0.4, running); };
    frame(body);
    frame(body);   // a modal appears on the frame after it is opened
    const ImGuiWindow* modal = ImGui::FindWindowByName("Working");
    ASSERT_NE(modal, nullptr);
    ASSERT_TRUE(modal->Active);
    const ImGuiID cancelId = ImHashStr("Cancel", 0, modal->ID);
    const float x = modal->Pos.x + 20.0f;
    const float y = findItem(cancelId, x, modal->Pos.y, modal->Pos.y + modal->Size.y, body);
    ASSERT_GE(y, 0.0f) << "the Cancel button was never hovered";
    EXPECT_FALSE(cancelled);
    click(x, y, body);
    EXPECT_TRUE(cancelled);
    running = false;
    frame(body);
    bool open = true;
    frame([&] {
        body();
        open = ImGui::IsPopupOpen("Working");
    });
    EXPECT_FALSE(open);
}

TEST_F(ImGuiNull, SpaceMouseCheckboxTurnsNavigationOff) {
    ui::EditorState state;
    state.spaceMouseStatus = "SpaceNavigator (046d:c626)";
    ImGuiID boxId = 0;
    auto body = [&] {
        boxId = ImGui::GetID("Navigate with it");
        ui::drawSettingsPanel(state);
    };
    ImGui::GetIO().DisplaySize = ImVec2(1280, 1100);
    windowHeight = 1100;   // the whole panel, no scrolling
    frame(body);
    const float y = findItem(boxId, 20.0f, 0.0f, 1100.0f, body);
    ASSERT_GE(y, 0.0f) << "no 'Navigate with it' checkbox";
    ASSERT_TRUE(state.spaceMouse.enabled);
    click(20.0f, y, body);
    EXPECT_FALSE(state.spaceMouse.enabled);
}

TEST_F(ImGuiNull, FiltersPanelTogglesTheHeatmapWithOrWithoutAVolume) {
    ui::EditorState state;
    renderer::Camera camera;
    camera.distance = 1.2;
    const renderer::ImagePlane plane = renderer::makeImagePlane(camera, {32, 32, 46}, 60.0, 512, 512);
    for (bool withVolume : {false, true}) {
        SCOPED_TRACE(withVolume ? "with a volume" : "without a volume");
        state.showHeatmap = state.settings.heatmap = false;
        bool changed = false;
        auto body = [&] {
            ui::FiltersView view;
            if (withVolume) {
                view.plane = &plane;
                view.dims = {64, 64, 93};
                view.radius = 60.0;
                view.patches = std::array<uint64_t, 3>{10, 0, 30};
            }
            changed |= ui::drawFiltersPanel(state, view).settingsChanged;
        };
        frame(body);
        EXPECT_FALSE(changed);
        // The checkbox is the panel's first widget (inside a table, so found by clicking down the panel).
        for (float y = 0.0f; y < 120.0f && !changed; y += 2.0f) click(20.0f, y, body);
        EXPECT_TRUE(changed);
        EXPECT_TRUE(state.showHeatmap);
        EXPECT_TRUE(state.settings.heatmap) << "the renderer would not draw the heatmap shown";
    }
}

TEST_F(ImGuiNull, FiltersPanelAsksToMeasureAndToCancelAndShowsEachFiltersRow) {
    ui::EditorState state;
    renderer::Camera camera;
    const renderer::ImagePlane plane = renderer::makeImagePlane(camera, {32, 32, 46}, 60.0, 512, 512);
    ui::FiltersView view;
    view.plane = &plane;
    view.dims = {64, 64, 93};
    view.radius = 60.0;
    view.cropPx = 96;
    ui::FiltersChanges seen;
    auto body = [&] {
        const ui::FiltersChanges c = ui::drawFiltersPanel(state, view);
        seen.measure |= c.measure;
        seen.cancel |= c.cancel;
        seen.settingsChanged |= c.settingsChanged;
    };
    // The cost column is the rightmost third of the panel: click down it until a button answers.
    auto clickInCostColumn = [&](bool ui::FiltersChanges::*answer) {
        for (float y = 0.0f; y < 160.0f && !(seen.*answer); y += 3.0f)
            for (float x = 280.0f; x < 395.0f && !(seen.*answer); x += 12.0f) click(x, y, body);
    };
    frame(body);
    clickInCostColumn(&ui::FiltersChanges::measure);
    EXPECT_TRUE(seen.measure) << "no Measure button";
    EXPECT_FALSE(seen.settingsChanged);

    view.measuring = true;
    view.truthProgress = 0.4;
    view.measurements = {{.filter = renderer::FilterMode::Reconstruction, .frameMs = 12.5, .rmse = 0.02, .psnrDb = 34.0}};
    seen = {};
    frame(body);
    clickInCostColumn(&ui::FiltersChanges::cancel);
    EXPECT_TRUE(seen.cancel) << "no Cancel button while measuring";
    EXPECT_FALSE(seen.measure) << "Measure offered while a measurement runs";

    // Surface splats have no ground truth: nothing to ask for. Shading and X-ray have their own.
    view.measuring = false;
    state.settings.surfaceFlatten = 4.0;
    seen = {};
    frame(body);
    clickInCostColumn(&ui::FiltersChanges::measure);
    EXPECT_FALSE(seen.measure);
    state.settings.surfaceFlatten = 1.0;
    state.settings.shading = renderer::SplatSettings::Shading::PerSplat;
    seen = {};
    frame(body);
    clickInCostColumn(&ui::FiltersChanges::measure);
    EXPECT_TRUE(seen.measure) << "shading has a ground truth";
    state.settings.shading = renderer::SplatSettings::Shading::None;
    state.settings.compositing = renderer::Compositing::XRay;
    seen = {};
    frame(body);
    clickInCostColumn(&ui::FiltersChanges::measure);
    EXPECT_TRUE(seen.measure) << "X-ray has a ground truth";
}

// At the widths the editor gives the Filters tab (800x600 and 1280x800 windows), no text is cut off
// by its column: headings wrap, and a narrow cost column lists each filter over two lines.
TEST_F(ImGuiNull, FiltersPanelTextFitsItsColumnsInSmallAndLargeWindows) {
    ui::EditorState state;
    const renderer::ImagePlane plane = renderer::makeImagePlane(renderer::Camera{}, {32, 32, 46}, 60.0, 512, 512);
    ui::FiltersView view;
    view.plane = &plane;
    view.dims = {64, 64, 93};
    view.radius = 60.0;
    view.cropPx = 96;
    view.patches = std::array<uint64_t, 3>{10, 0, 30};
    view.measurements = {{.filter = renderer::FilterMode::Reconstruction, .frameMs = 112.5, .rmse = 0.0324, .psnrDb = 29.78},
                         {.filter = renderer::FilterMode::Adaptive, .frameMs = 63.5, .rmse = 0.0329, .psnrDb = 29.64}};
    view.measurementsStale = true;
    for (const float width : {560.0f, 955.0f}) {
        windowWidth = width;
        frame([&] { ui::drawFiltersPanel(state, view); });
        EXPECT_EQ(textCutOff(), "") << "panel " << width << " px wide";
    }
}

// The other panels at the widths the editor gives them (left column and bottom strip, 800x600 and
// 1280x800 windows): no text is cut off by its window or column.
TEST_F(ImGuiNull, PanelTextFitsInSmallAndLargeWindows) {
    ui::EditorState state;
    renderer::Volume volume;
    volume.name = "headsq";
    volume.dims = {64, 64, 93};
    volume.spacing = {3.2, 3.2, 1.5};
    volume.range = {0.0f, 3926.0f};
    ui::StatsView stats;
    stats.volume = &volume;
    stats.visibleSplats = 30903;
    stats.glRenderer = "llvmpipe (LLVM 15.0.6, 256 bits)";
    stats.frame.splatsDrawn = 32327;
    stats.frame.gpuMs = 47.1;
    stats.sceneBytes = 1284310;
    stats.workingBytes = 29465100;
    ui::PerfHistory history;
    for (uint64_t k = 1; k <= 12; ++k) {   // renders with times, so the chart and the summary are drawn
        renderer::FrameStats f;
        f.frame = f.gpuFrame = k;
        f.cpuMs = 74.7;
        f.gpuMs = 60.0 + double(k);
        f.splatsDrawn = 32327;
        f.passMs[size_t(renderer::GpuPass::Splats)] = 9.1;
        f.passMs[size_t(renderer::GpuPass::Composite)] = 40.4;
        history.addRender(f, 95.2);
        history.addTimes(f);
    }
    windowHeight = 3000;   // only the width is under test
    const std::vector<float> leftColumn{205.0f, 320.0f}, bottomStrip{560.0f, 955.0f};
    const std::tuple<const char*, std::function<void()>, std::vector<float>> panels[] = {
        {"Settings", [&] { ui::drawSettingsPanel(state); }, leftColumn},
        {"Transfer function",
         [&] { ui::drawTransferFunctionPanel(state, {.histogram = nullptr, .window = {0, 3926}, .dataRange = {}, .percentile = {}, .visible = {}}); }, leftColumn},
        {"Stats", [&] { ui::drawStatsPanel(stats); }, bottomStrip},
        {"Help", [&] { ui::drawHelpPanel(); }, bottomStrip},
        {"Performance", [&] { ui::drawPerformancePanel(state, history); }, bottomStrip},
    };
    for (const auto& [name, draw, widths] : panels)
        for (const float width : widths) {
            windowWidth = width;
            frame(draw);
            EXPECT_EQ(textCutOff(), "") << name << ", " << width << " px wide";
        }
}

// == Stats

// The Stats panel of a volume in the bottom strip of a 1280x800 window (955 px: the lines unwrapped).
class StatsPanel : public ImGuiNull {
  protected:
    renderer::Volume volume;
    ui::StatsView stats;
    void SetUp() override {
        ImGuiNull::SetUp();
        stats.volume = &volume;
        windowWidth = 955;
    }
    std::string text() { return loggedText([&] { ui::drawStatsPanel(stats); }); }
};

// The Stats panel gives the GPU memory of the scene (bytes a voxel) and of the tiled passes' buffers.
TEST_F(StatsPanel, GivesTheGpuMemoryOfTheSceneAndThePasses) {
    volume.name = "headsq";
    volume.dims = {64, 64, 93};
    EXPECT_THAT(text(), testing::Not(testing::HasSubstr("memory"))) << "nothing rendered yet";
    stats.sceneBytes = 921846;      // 2.42 bytes for each of the 380,928 voxels
    stats.workingBytes = 29465100;
    EXPECT_THAT(text(), testing::HasSubstr("memory  scene 2.42 bytes a voxel (0.9 MiB)\n        passes 28.1 MiB"));
}

// The Stats panel says how the file's axes are drawn: nothing for the world's own axes, the angle the
// view turns by for oblique ones, and that sheared ones are resampled (or not applied, unaligned).
TEST_F(StatsPanel, SaysHowTheFilesAxesAreDrawn) {
    volume.name = "axes";
    volume.dims = {2, 2, 2};
    EXPECT_THAT(text(), testing::Not(testing::HasSubstr("axes ")));
    volume.directions = glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(30.0), glm::dvec3(1, 2, 3)));
    EXPECT_THAT(text(), testing::HasSubstr("axes    oblique, turned 30 degrees"));
    volume.directions = glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(170.0), glm::dvec3(0, 0, 1)));
    EXPECT_THAT(text(), testing::HasSubstr("turned 170 degrees"));
    volume.directions = glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(0.0057), glm::dvec3(1, 0, 0)));
    EXPECT_THAT(text(), testing::HasSubstr("turned 0.0057 degrees")) << "a slight tilt is not 0";
    volume.directions[1] = glm::normalize(glm::dvec3(0.6, 0.8, 0.0));
    EXPECT_THAT(text(), testing::HasSubstr("axes    sheared, not applied"));   // a volume not aligned
    const renderer::Volume resampled = renderer::alignedToWorldAxes(volume);
    stats.volume = &resampled;
    EXPECT_THAT(text(), testing::HasSubstr("axes    sheared, resampled"));
}
