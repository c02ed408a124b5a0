// The heatmap over the image: its legend's thresholds are the classifier's, the viewport draws the image
// and the heatmap with the opacity the Filters panel sets, and the regime tour dollies the camera out and
// back and stops at the user's camera input.
#include "imgui_null.h"
#include "renderer/math/classifier.h"
#include "ui/heatmap_legend.h"
#include "ui/panels.h"
#include "ui/regime_tour.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

using ::testing::HasSubstr;

namespace {

// headsq's grid (64 x 64 x 93, unit spacing) seen from 2.5 bounding radii with a 30 degree fov at
// 955 x 545 px: the editor's default view of it in a 1280x800 window.
constexpr double kRadius = 60.0;
renderer::ImagePlane headsqPlane(double distance = 2.5, double fovYDeg = 30.0) {
    renderer::Camera camera;
    camera.distance = distance;
    camera.fovYDeg = fovYDeg;
    return renderer::makeImagePlane(camera, {32, 32, 46}, kRadius, 955, 545);
}

std::string fixed2(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", v);
    return text;
}

// The alpha of the vertices drawn with each texture (ImGui's draw data after a frame), by texture name.
std::map<intptr_t, int> alphaPerTexture() {
    std::map<intptr_t, int> alpha;
    const ImDrawData* data = ImGui::GetDrawData();
    for (int l = 0; l < data->CmdListsCount; ++l) {
        const ImDrawList* list = data->CmdLists[l];
        for (const ImDrawCmd& cmd : list->CmdBuffer) {
            const auto id = reinterpret_cast<intptr_t>(cmd.TextureId);
            if ((id != 11 && id != 12) || cmd.ElemCount == 0) continue;
            const ImDrawVert& v = list->VtxBuffer[int(cmd.VtxOffset + list->IdxBuffer[int(cmd.IdxOffset)])];
            alpha[id] = int(v.col >> IM_COL32_A_SHIFT & 0xFF);
        }
    }
    return alpha;
}

} // namespace

TEST(HeatmapLegend, ThresholdsAreTheClassifiersInPixelsAndDepthsForAKnownCamera) {
    for (const double fov : {30.0, 60.0}) {
        SCOPED_TRACE("fov " + std::to_string(fov));
        const renderer::ImagePlane plane = headsqPlane(2.5, fov);
        renderer::SplatSettings s;
        s.filter = renderer::FilterMode::Adaptive;
        const ui::HeatmapLegend legend = ui::heatmapLegend({1, 1, 1}, kRadius, plane, s, fov);
        const renderer::AdaptiveThresholds t = renderer::adaptiveThresholds({1, 1, 1}, plane, s);
        EXPECT_EQ(legend.reconstructionAbovePx, t.reconstructionAbovePx);
        EXPECT_EQ(legend.lowPassBelowPx, t.lowPassBelowPx);
        // The depths are where the classifier itself changes its answer, in bounding radii.
        const double nearer = legend.reconstructionNearer * kRadius,
                     farther = legend.lowPassFarther * kRadius;
        EXPECT_EQ(renderer::classifyDepth(nearer * 0.999, plane, t), renderer::FilterMode::Reconstruction);
        EXPECT_EQ(renderer::classifyDepth(nearer * 1.001, plane, t), renderer::FilterMode::Ewa);
        EXPECT_EQ(renderer::classifyDepth(farther * 0.999, plane, t), renderer::FilterMode::Ewa);
        EXPECT_EQ(renderer::classifyDepth(farther * 1.001, plane, t), renderer::FilterMode::LowPass);
        // A wider fov makes every kernel smaller on screen: the thresholds move nearer the eye.
        EXPECT_LT(legend.reconstructionNearer, legend.lowPassFarther);
        // The rows say those figures, rounded as shown.
        EXPECT_THAT(legend.rows[0], HasSubstr(fixed2(t.reconstructionAbovePx) + " px"));
        EXPECT_THAT(legend.rows[0], HasSubstr("nearer than " + fixed2(legend.reconstructionNearer)));
        EXPECT_THAT(legend.rows[2], HasSubstr(fixed2(t.lowPassBelowPx) + " px"));
        EXPECT_THAT(legend.rows[2], HasSubstr("farther than " + fixed2(legend.lowPassFarther)));
        EXPECT_THAT(legend.footer, HasSubstr("fov " + std::to_string(int(fov)) + " deg"));
    }
    EXPECT_LT(ui::heatmapLegend({1, 1, 1}, kRadius, headsqPlane(2.5, 60.0), {}, 60.0).reconstructionNearer,
              ui::heatmapLegend({1, 1, 1}, kRadius, headsqPlane(2.5, 30.0), {}, 30.0).reconstructionNearer);
}

TEST_F(ImGuiNull, ViewportDrawsTheHeatmapOverTheImageWithTheOpacitySet) {
    ui::EditorState state;
    const renderer::ImagePlane plane = headsqPlane();
    ui::ViewportOverlay overlay;
    overlay.heatmapTexture = 12; // texture names the draw data carries; nothing samples them here
    overlay.legend = ui::heatmapLegend({1, 1, 1}, kRadius, plane, state.settings, 30.0);
    auto body = [&] { ui::drawViewportPanel(state, 11, overlay); };
    // Heatmap off: the image alone, opaque.
    frame(body);
    EXPECT_EQ(alphaPerTexture(), (std::map<intptr_t, int>{{11, 255}}));
    // GL blends src x alpha + dst x (1 - alpha): at 0 the image alone, at 1 the heatmap alone, between
    // the heatmap at that alpha over the opaque image.
    state.showHeatmap = true;
    for (const auto& [opacity, expected] : {std::pair{0.0, std::map<intptr_t, int>{{11, 255}}},
                                            std::pair{1.0, std::map<intptr_t, int>{{12, 255}}},
                                            std::pair{0.5, std::map<intptr_t, int>{{11, 255}, {12, 128}}}}) {
        state.heatmapOpacity = opacity;
        frame(body);
        EXPECT_EQ(alphaPerTexture(), expected) << "opacity " << opacity;
    }
    // No heatmap from the renderer yet (just turned on): the image alone.
    overlay.heatmapTexture = 0;
    frame(body);
    EXPECT_EQ(alphaPerTexture(), (std::map<intptr_t, int>{{11, 255}}));
}

TEST_F(ImGuiNull, FiltersPanelOpacitySliderDraggedToItsEndsGivesImageOnlyAndHeatmapOnly) {
    ui::EditorState state;
    state.showHeatmap = state.settings.heatmap = true;
    state.heatmapOpacity = 0.5;
    const renderer::ImagePlane plane = headsqPlane();
    ui::FiltersView view;
    view.plane = &plane;
    view.dims = {64, 64, 93};
    view.radius = kRadius;
    auto body = [&] { ui::drawFiltersPanel(state, view); };
    frame(body);
    // The slider follows the Heatmap checkbox (beside it, or under it in a narrow column): find it by
    // where a short drag changes the opacity, right of the checkbox's label (a plain click types).
    float sliderY = -1.0f, sliderX = 110.0f;
    for (float y = 20.0f; y < 100.0f && sliderY < 0.0f; y += 2.0f) {
        const double before = state.heatmapOpacity;
        mouse(sliderX, y, true);
        frame(body);
        mouse(sliderX + 20.0f, y, true);
        frame(body);
        mouse(sliderX + 20.0f, y, false);
        frame(body);
        if (state.heatmapOpacity != before) sliderY = y;
    }
    ASSERT_GE(sliderY, 0.0f) << "no opacity slider";
    // Drag past the left end, then past the right end: 0 and 1 exactly.
    mouse(sliderX, sliderY, true);
    frame(body);
    mouse(-50.0f, sliderY, true);
    frame(body);
    EXPECT_EQ(state.heatmapOpacity, 0.0);
    mouse(500.0f, sliderY, true);
    frame(body);
    EXPECT_EQ(state.heatmapOpacity, 1.0);
    mouse(500.0f, sliderY, false);
    frame(body);
}

TEST(RegimeTour, DolliesFromTheStartToNearThenFarAndBackSmoothly) {
    const ui::RegimeTour tour(2.5, 1.2, 9.0);
    EXPECT_DOUBLE_EQ(tour.distanceAt(0.0), 2.5);
    EXPECT_DOUBLE_EQ(tour.distanceAt(ui::RegimeTour::kDurationS), 2.5);
    double nearest = 1e9, farthest = 0.0, largestStep = 0.0, previous = 2.5;
    for (int frame = 1; frame <= int(ui::RegimeTour::kDurationS * 60.0); ++frame) {
        const double d = tour.distanceAt(frame / 60.0);
        nearest = std::min(nearest, d), farthest = std::max(farthest, d);
        largestStep = std::max(largestStep, std::abs(std::log(d / previous)));
        previous = d;
    }
    // Sampled at 60 /s, the turning points are passed within a frame: the ease leaves them flat.
    EXPECT_NEAR(nearest, 1.2, 1e-3);
    EXPECT_NEAR(farthest, 9.0, 1e-3);
    // Smooth: no frame at 60 /s moves the camera by more than 3 % of its distance.
    EXPECT_LT(largestStep, std::log(1.03));
}

TEST(RegimeTour, GoesFromTheReconstructionDepthToPastTheLowPassDepthWithinItsRange) {
    const ui::RegimeTour tour = ui::makeRegimeTour(2.5, 2.0, 6.0);
    EXPECT_DOUBLE_EQ(tour.nearDistance(), 1.6); // the centre at 0.8 x the reconstruction depth
    EXPECT_DOUBLE_EQ(tour.farDistance(), 7.5);  // and at 1.25 x the low-pass depth
    const ui::RegimeTour clamped = ui::makeRegimeTour(2.5, 0.1, 1e6);
    EXPECT_DOUBLE_EQ(clamped.nearDistance(), ui::kMinDistance);
    EXPECT_DOUBLE_EQ(clamped.farDistance(), ui::kMaxTourDistance);
    // Regimes close together: far is still twice near, so the camera moves.
    EXPECT_DOUBLE_EQ(ui::makeRegimeTour(2.5, 3.0, 2.0).farDistance(), 4.8);
}

TEST_F(ImGuiNull, RegimeTourStartsFromTheFiltersPanelMovesOutAndBackAndStopsAtAViewportDrag) {
    ui::EditorState state;
    const renderer::ImagePlane plane = headsqPlane();
    ui::FiltersView view;
    view.plane = &plane;
    view.dims = {64, 64, 93};
    view.radius = kRadius;
    auto filters = [&] { ui::drawFiltersPanel(state, view); };
    // 1. The button (the first column, under the heatmap's row) starts a tour and turns the heatmap on.
    frame(filters);
    for (float y = 20.0f; y < 100.0f && !state.tour; y += 2.0f)
        click(30.0f, y, filters);
    ASSERT_TRUE(state.tour) << "no Regime tour button";
    EXPECT_TRUE(state.showHeatmap);
    EXPECT_TRUE(state.settings.heatmap);
    // 2. Frames of the viewport with the app's step after each: the camera goes out and comes back.
    bool userMoved = false;
    auto viewport = [&] { userMoved = ui::drawViewportPanel(state, 11).cameraChanged; };
    const double start = state.camera.distance;
    double farthest = start;
    int frames = 0;
    mouse(200.0f, 300.0f, false);
    while (state.tour && frames < 1000) {
        frame(viewport);
        EXPECT_TRUE(ui::stepRegimeTour(state, 1.0 / 60.0, userMoved));
        farthest = std::max(farthest, state.camera.distance);
        ++frames;
    }
    EXPECT_FALSE(state.tour);
    EXPECT_NEAR(frames, ui::RegimeTour::kDurationS * 60.0, 1.0);
    EXPECT_GT(farthest, 2.0 * start) << "the tour did not go out";
    EXPECT_NEAR(state.camera.distance, start, 1e-9) << "the tour did not come back";
    // 3. Another tour, stopped half-way by a left drag in the viewport: the camera stays where it was,
    //    turned by the drag, and the next frames do not move it.
    state.tour = ui::makeRegimeTour(state.camera.distance, 2.0, 6.0);
    for (int i = 0; i < 120; ++i) {
        frame(viewport);
        ui::stepRegimeTour(state, 1.0 / 60.0, userMoved);
    }
    const double halfWay = state.camera.distance, azimuth = state.camera.azimuthDeg;
    mouse(200.0f, 300.0f, true);
    frame(viewport);
    mouse(230.0f, 300.0f, true);
    frame(viewport);
    EXPECT_TRUE(userMoved);
    EXPECT_FALSE(ui::stepRegimeTour(state, 1.0 / 60.0, userMoved));
    EXPECT_FALSE(state.tour) << "a drag did not stop the tour";
    mouse(230.0f, 300.0f, false);
    frame(viewport);
    EXPECT_FALSE(ui::stepRegimeTour(state, 1.0 / 60.0, userMoved));
    EXPECT_EQ(state.camera.distance, halfWay);
    EXPECT_NE(state.camera.azimuthDeg, azimuth);
}
