// The transfer-function editor: the curve rules as pure functions, then the panel driven through
// ImGui (drag, add, remove, the point's fields, files).
#include "imgui_null.h"
#include "test_paths.h"
#include "ui/panels.h"
#include "ui/tf_editor.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace {

using renderer::TransferFunction;
using testing::HasSubstr;
using ui::CanvasPoint;
using ui::Rect;

// Colour stops and opacity points at 0, half and all of `window` (data units).
TransferFunction threePoints(renderer::ValueRange window = {0.0f, 1.0f}) {
    return renderer::inDataUnits(
        renderer::fromSharedPoints("three", {{0.0, {0, 0, 0}, 0.0}, {0.5, {1, 0, 0}, 0.5}, {1.0, {1, 1, 1}, 1.0}}),
        window);
}

bool sorted(const TransferFunction& tf) {
    for (size_t i = 1; i < tf.opacities.size(); ++i)
        if (tf.opacities[i].value < tf.opacities[i - 1].value) return false;
    for (size_t i = 1; i < tf.colours.size(); ++i)
        if (tf.colours[i].value < tf.colours[i - 1].value) return false;
    return true;
}

constexpr renderer::ValueRange kUnit{0.0f, 1.0f};

} // namespace

// == The rules

TEST(TfCurve, CanvasMappingRoundTripsAndClampsToTheDomain) {
    const Rect canvas{10, 20, 300, 120};
    for (double v : {0.0, 0.25, 0.5, 1.0})
        for (double a : {0.0, 0.3, 1.0}) {
            double value = -1, opacity = -1;
            ui::canvasToTf(canvas, ui::tfToCanvas(canvas, v, a), value, opacity);
            EXPECT_NEAR(value, v, 1e-6);
            EXPECT_NEAR(opacity, a, 1e-6);
        }
    EXPECT_EQ(ui::tfToCanvas(canvas, 0.0, 0.0).y, canvas.bottom());   // opacity 0 at the bottom
    double value = -1, opacity = -1;
    ui::canvasToTf(canvas, {-50, -50}, value, opacity);   // left of and above the canvas
    EXPECT_EQ(value, 0.0);
    EXPECT_EQ(opacity, 1.0);
    ui::canvasToTf(Rect{0, 0, 0, 0}, {5, 5}, value, opacity);   // an empty canvas: no division by zero
    EXPECT_EQ(value, 0.0);
    EXPECT_EQ(opacity, 0.0);
}

// Within kOpacitySnapPx of the baseline a drag gives exactly 0 (no voxel of that value is drawn), near
// the top exactly 1; a little further it gives what the height says.
TEST(TfCurve, TheBaselineSnapsToExactlyZeroAndTheTopToOne) {
    const Rect canvas{10, 20, 300, 120};
    double value = -1, opacity = -1;
    ui::canvasToTf(canvas, {100, canvas.bottom() - 2.0f}, value, opacity);
    EXPECT_EQ(opacity, 0.0);
    ui::canvasToTf(canvas, {100, canvas.y + 2.0f}, value, opacity);
    EXPECT_EQ(opacity, 1.0);
    ui::canvasToTf(canvas, {100, canvas.bottom() - 12.0f}, value, opacity);
    EXPECT_NEAR(opacity, 0.1, 1e-6);
    ui::canvasToTf(canvas, {100, canvas.bottom() - 2.0f}, value, opacity, ui::OpacityAxis::Log);
    EXPECT_EQ(opacity, 0.0);
}

// The log axis spans kLogOpacityDecades decades below 1: each decade a third of the height, the faint
// values round-trip, and 0 (or anything under the floor) sits on the baseline.
TEST(TfCurve, TheLogAxisOpensTheFaintRangeAndRoundTrips) {
    const Rect canvas{10, 20, 300, 120};
    const auto log = ui::OpacityAxis::Log;
    EXPECT_NEAR(ui::tfToCanvas(canvas, 0.5, 0.01, log).y, canvas.bottom() - canvas.h / 3.0f, 1e-3);
    EXPECT_NEAR(ui::tfToCanvas(canvas, 0.5, 0.1, log).y, canvas.bottom() - 2.0f * canvas.h / 3.0f, 1e-3);
    EXPECT_EQ(ui::tfToCanvas(canvas, 0.5, 0.0, log).y, canvas.bottom());
    EXPECT_EQ(ui::tfToCanvas(canvas, 0.5, 1e-4, log).y, canvas.bottom());
    for (double a : {0.002, 0.005, 0.03, 0.3, 1.0}) {
        double value = -1, opacity = -1;
        ui::canvasToTf(canvas, ui::tfToCanvas(canvas, 0.5, a, log), value, opacity, log);
        EXPECT_NEAR(opacity, a, 1e-5 * a) << a;
    }
    // On the linear axis 0.005 is under a pixel above the baseline; here it is 28 px up.
    EXPECT_GT(canvas.bottom() - ui::tfToCanvas(canvas, 0.5, 0.005, log).y, 27.0f);
}

TEST(TfCurve, InsertingAPointOnTheCurveLeavesTheTableAsItWas) {
    for (double v : {0.0, 0.05, 0.3, 0.5, 0.77, 1.0}) {
        TransferFunction tf = threePoints();
        const renderer::Lut before = renderer::bakeLut(tf, kUnit);
        const int i = ui::insertOpacityPoint(tf, v, renderer::evaluate(tf, v).a);
        const int k = ui::insertColourStop(tf, v);
        ASSERT_EQ(tf.opacities.size(), 4u);
        ASSERT_EQ(tf.colours.size(), 4u);
        EXPECT_EQ(tf.opacities[size_t(i)].value, v);
        EXPECT_EQ(tf.colours[size_t(k)].value, v);
        EXPECT_TRUE(sorted(tf));
        const renderer::Lut after = renderer::bakeLut(tf, kUnit);
        double worst = 0;
        for (size_t c = 0; c < before.size(); ++c)
            for (int ch = 0; ch < 4; ++ch) worst = std::max(worst, double(std::abs(after[c][ch] - before[c][ch])));
        EXPECT_LT(worst, 1e-6) << "inserting at " << v << " changed the table";
    }
    // Off the curve, only the two intervals around the new point change, and only opacity.
    TransferFunction tf = threePoints();
    const renderer::Lut before = renderer::bakeLut(tf, kUnit);
    ui::insertOpacityPoint(tf, 0.25, 0.9);
    const renderer::Lut after = renderer::bakeLut(tf, kUnit);
    for (size_t k = renderer::kLutSize / 2; k < before.size(); ++k) ASSERT_EQ(after[k], before[k]) << k;
    for (size_t k = 0; k < before.size(); ++k) ASSERT_EQ(glm::vec3(after[k]), glm::vec3(before[k])) << k;
    EXPECT_NEAR(after[renderer::kLutSize / 4].a, 0.9, 1e-3);
}

TEST(TfCurve, ADraggedPointStaysBetweenItsNeighbours) {
    TransferFunction tf = threePoints();
    ui::moveOpacityPoint(tf, 1, 0.9, 2.0);
    EXPECT_EQ(tf.opacities[1].value, 0.9);
    EXPECT_EQ(tf.opacities[1].opacity, 1.0);
    ui::moveOpacityPoint(tf, 1, 1.5, -1.0);   // past the last point
    EXPECT_EQ(tf.opacities[1].value, 1.0);
    EXPECT_EQ(tf.opacities[1].opacity, 0.0);
    ui::moveOpacityPoint(tf, 1, -3.0, 0.4);   // past the first
    EXPECT_EQ(tf.opacities[1].value, 0.0);
    ui::moveOpacityPoint(tf, 0, 0.6, 0.2);    // the first point stops at its right neighbour
    EXPECT_EQ(tf.opacities[0].value, 0.0);
    ui::moveOpacityPoint(tf, 2, 7.0, 1.0);    // the last one has no right neighbour: data units go on
    EXPECT_EQ(tf.opacities[2].value, 7.0);
    ui::moveOpacityPoint(tf, 1, std::nan(""), 0.7);   // NaN keeps that coordinate
    EXPECT_EQ(tf.opacities[1].value, 0.0);
    EXPECT_EQ(tf.opacities[1].opacity, 0.7);
    ui::moveOpacityPoint(tf, 7, 0.5, 0.5);    // no such point: nothing happens
    ui::moveOpacityPoint(tf, -1, 0.5, 0.5);
    ui::moveColourStop(tf, 1, 2.0);           // a colour stop too stops at its neighbour
    EXPECT_EQ(tf.colours[1].value, 1.0);
    ui::moveColourStop(tf, 9, 0.5);
    EXPECT_TRUE(sorted(tf));
    EXPECT_EQ(tf.opacities.size(), 3u);
    EXPECT_EQ(tf.colours.size(), 3u);
}

// The two functions are apart: moving, adding or removing a colour stop leaves every opacity point as it
// was, and the reverse.
TEST(TfCurve, ColourStopEditsLeaveOpacityAloneAndTheReverse) {
    TransferFunction tf = threePoints();
    const auto opacities = tf.opacities;
    ui::moveColourStop(tf, 1, 0.8);
    ui::insertColourStop(tf, 0.3);
    ui::removeColourStop(tf, 0);
    EXPECT_EQ(tf.opacities, opacities);
    const auto colours = tf.colours;
    ui::moveOpacityPoint(tf, 1, 0.2, 0.9);
    ui::insertOpacityPoint(tf, 0.6, 0.1);
    ui::removeOpacityPoint(tf, 0);
    EXPECT_EQ(tf.colours, colours);
}

TEST(TfCurve, RemovingKeepsAStartAndAnEnd) {
    TransferFunction tf = threePoints();
    EXPECT_FALSE(ui::removeOpacityPoint(tf, 3));
    EXPECT_FALSE(ui::removeOpacityPoint(tf, -1));
    EXPECT_TRUE(ui::removeOpacityPoint(tf, 1));
    EXPECT_EQ(tf.opacities.size(), 2u);
    EXPECT_FALSE(ui::removeOpacityPoint(tf, 0));
    EXPECT_EQ(tf.opacities.size(), 2u);
    EXPECT_TRUE(ui::removeColourStop(tf, 1));
    EXPECT_FALSE(ui::removeColourStop(tf, 1));
    EXPECT_EQ(tf.colours.size(), 2u);
}

TEST(TfCurve, PickingFindsTheNearestPointWithinTheRadius) {
    const Rect canvas{0, 0, 200, 100};
    const renderer::ValueRange window{-1000.0f, 3000.0f};
    TransferFunction tf = threePoints(window);   // points at (0, 100), (100, 50), (200, 0)
    EXPECT_EQ(ui::pickOpacityPoint(tf, window, canvas, {104, 47}, 8), 1);
    EXPECT_EQ(ui::pickOpacityPoint(tf, window, canvas, {120, 50}, 8), -1);
    EXPECT_EQ(ui::pickOpacityPoint(tf, window, canvas, {3, 98}, 8), 0);
    ui::insertOpacityPoint(tf, 1080.0, 0.5);   // two points 4 px apart: the nearer wins
    EXPECT_EQ(ui::pickOpacityPoint(tf, window, canvas, {103, 50}, 8), 2);
    EXPECT_EQ(ui::pickOpacityPoint(tf, window, canvas, {99, 50}, 8), 1);
    // Colour stops: across only, inside the bar's rows.
    const Rect bar{0, 120, 200, 20};
    EXPECT_EQ(ui::pickColourStop(tf, window, bar, {96, 130}, 6), 1);
    EXPECT_EQ(ui::pickColourStop(tf, window, bar, {96, 110}, 6), -1);   // above the bar
    EXPECT_EQ(ui::pickColourStop(tf, window, bar, {150, 130}, 6), -1);
    EXPECT_EQ(ui::pickColourStop(tf, window, bar, {198, 139}, 6), 2);
}

TEST(TfCurve, HistoryUndoesAndRedoesAndForgetsRedoOnANewEdit) {
    ui::TfHistory h;
    TransferFunction tf = threePoints();
    EXPECT_FALSE(h.undoInto(tf));
    const TransferFunction a = tf;
    h.record(tf);
    ui::moveOpacityPoint(tf, 1, 0.7, 0.2);
    const TransferFunction b = tf;
    h.record(tf);
    ui::removeOpacityPoint(tf, 1);
    ASSERT_TRUE(h.undoInto(tf));
    EXPECT_EQ(tf, b);
    ASSERT_TRUE(h.undoInto(tf));
    EXPECT_EQ(tf, a);
    EXPECT_FALSE(h.undoInto(tf));
    ASSERT_TRUE(h.redoInto(tf));
    EXPECT_EQ(tf, b);
    h.record(tf);   // a new edit: the redone-away future is gone
    ui::insertOpacityPoint(tf, 0.1, 0.1);
    EXPECT_FALSE(h.redoInto(tf));
    for (size_t i = 0; i < 3 * ui::kTfHistorySteps; ++i) h.record(tf);
    EXPECT_EQ(h.undo.size(), ui::kTfHistorySteps);
}

TEST(TfCurve, DataUnitsMapOntoTheWindow) {
    const renderer::ValueRange window{-1000.0f, 3000.0f};
    EXPECT_DOUBLE_EQ(ui::toDataUnits(0.25, window), 0.0);
    EXPECT_DOUBLE_EQ(ui::fromDataUnits(1000.0, window), 0.5);
    EXPECT_EQ(ui::fromDataUnits(9000.0, window), 1.0);
    EXPECT_EQ(ui::fromDataUnits(5.0, renderer::ValueRange{2.0f, 2.0f}), 0.0);
}

// == The panel through ImGui

namespace {

class TfPanel : public ImGuiNull {
  protected:
    ui::EditorState state;
    renderer::ValueRange window{-1000.0f, 3000.0f};
    ui::TransferFunctionView view = [this] {
        ui::TransferFunctionView v;
        v.window = window, v.dataRange = {-1024.0f, 3071.0f}, v.percentile = {-900.0f, 1200.0f};
        v.visible = {100.0f, 400.0f};
        return v;
    }();
    bool changed = false;
    ImGuiID canvasId = 0, barId = 0;

    void SetUp() override {
        ImGuiNull::SetUp();
        state.tf = threePoints(window);
    }
    void draw() {
        canvasId = ImGui::GetID("##tf_canvas");
        barId = ImGui::GetID("##tf_colour_bar");
        changed |= ui::drawTransferFunctionPanel(state, view);
    }
    // A fraction of the window in data units, and the data-unit size of a pixel of `r`.
    double data(double fraction) const { return ui::toDataUnits(fraction, window); }
    double pixel(const Rect& r) const { return (double(window.hi) - window.lo) / r.w; }
    std::function<void()> body() {
        return [this] { draw(); };
    }
    // Opens the Preset combo and clicks `name` in it; false (after a failed assertion) if either is missing.
    bool pickPreset(const char* name) {
        ImGuiID comboId = 0;
        auto withCombo = [&] {
            comboId = ImGui::GetID("Preset");
            draw();
        };
        frame(withCombo);
        const float comboY = findItem(comboId, 40.0f, 0.0f, 700.0f, withCombo);
        EXPECT_GE(comboY, 0.0f) << "no Preset combo";
        if (comboY < 0.0f) return false;
        click(40.0f, comboY, withCombo);
        const ImGuiWindow* popup = ImGui::FindWindowByName("##Combo_00");
        EXPECT_NE(popup, nullptr);
        if (!popup) return false;
        const float itemY = findItem(ImHashStr(name, 0, popup->ID), 40.0f, comboY, comboY + 300.0f, withCombo);
        EXPECT_GE(itemY, 0.0f) << "the preset " << name << " was never hovered";
        if (itemY < 0.0f) return false;
        click(40.0f, itemY, withCombo);
        return true;
    }
    Rect findCanvas() { return findItemRect(canvasId, 700, body()); }
    // The colour bar's rectangle, found the same way below the canvas.
    Rect findColourBar(const Rect& canvas) {
        float top = -1, bottom = -1;
        for (float y = canvas.bottom(); y < canvas.bottom() + 80; y += 1) {
            mouse(canvas.x + 0.5f * canvas.w, y, false);
            frame(body());
            if (ImGui::GetCurrentContext()->HoveredId == barId) (top < 0 ? top : bottom) = y;
        }
        return {canvas.x, top, canvas.w, bottom + 1 - top};
    }
    void press(CanvasPoint p, int button) {
        ImGui::GetIO().MousePos = ImVec2(p.x, p.y);
        ImGui::GetIO().MouseDown[button] = true;
        frame(body());
    }
    void release(int button) {
        ImGui::GetIO().MouseDown[button] = false;
        frame(body());
    }
};

} // namespace

TEST_F(TfPanel, DraggingAPointMovesItByTheMouseAndStopsAtItsNeighbour) {
    const Rect canvas = findCanvas();
    ASSERT_GT(canvas.w, 100.0f);
    ASSERT_GT(canvas.h, 50.0f);
    EXPECT_FALSE(changed);
    // Grab the middle point a little off its centre: the grab offset keeps it from jumping.
    const CanvasPoint at = ui::tfToCanvas(canvas, 0.5, 0.5);
    press({at.x + 3, at.y - 2}, 0);
    EXPECT_EQ(state.tfSelected, 1);
    EXPECT_EQ(state.tf.opacities.size(), 3u) << "pressing on a point added one";
    EXPECT_FALSE(changed) << "a press without motion changed the TF";
    press({at.x + 3 + 0.2f * canvas.w, at.y - 2 - 0.1f * canvas.h}, 0);
    release(0);
    EXPECT_TRUE(changed);
    EXPECT_TRUE(state.tfEdited);
    // ImGui floors the mouse position: a pixel either way.
    EXPECT_NEAR(state.tf.opacities[1].value, data(0.7), pixel(canvas));
    EXPECT_NEAR(state.tf.opacities[1].opacity, 0.6, 1.0 / canvas.h);
    // Dragged far past the last point, it stops there.
    const CanvasPoint now =
        ui::tfToCanvas(canvas, ui::windowFraction(state.tf.opacities[1].value, window), state.tf.opacities[1].opacity);
    press(now, 0);
    press({now.x + canvas.w, now.y}, 0);
    release(0);
    EXPECT_EQ(state.tf.opacities[1].value, double(window.hi));
    EXPECT_TRUE(sorted(state.tf));
}

TEST_F(TfPanel, ClickingEmptySpaceAddsAPointAndRightClickingRemovesIt) {
    const Rect canvas = findCanvas();
    const TransferFunction before = state.tf;
    const CanvasPoint spot = ui::tfToCanvas(canvas, 0.25, 0.8);
    press(spot, 0);
    release(0);
    ASSERT_EQ(state.tf.opacities.size(), 4u);
    EXPECT_EQ(state.tf.colours, before.colours) << "an opacity point changed the colours";
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tfSelected, 1);
    const renderer::OpacityPoint added = state.tf.opacities[1];
    EXPECT_NEAR(added.value, data(0.25), pixel(canvas));
    EXPECT_NEAR(added.opacity, 0.8, 1.0 / canvas.h);

    changed = false;
    press(ui::tfToCanvas(canvas, 0.6, 0.95), 1);   // right-click on empty space: nothing
    release(1);
    EXPECT_EQ(state.tf.opacities.size(), 4u);
    EXPECT_FALSE(changed);
    press(ui::tfToCanvas(canvas, ui::windowFraction(added.value, window), added.opacity), 1);
    release(1);
    EXPECT_EQ(state.tf.opacities.size(), 3u);
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tfSelected, -1);
}

TEST_F(TfPanel, SaveWritesAFileThatLoadsBackAndBadFilesNameThemselves) {
    const auto dir = testing_support::testOutputDir("tf_panel");
    ImGuiID loadId = 0, saveId = 0;
    auto withButtons = [&] {
        loadId = ImGui::GetID("Load");
        saveId = ImGui::GetID("Save");
        draw();
    };
    frame(withButtons);
    const float y = findItem(loadId, 20.0f, 0.0f, 700.0f, withButtons);
    ASSERT_GE(y, 0.0f) << "the Load button was never hovered";
    const float saveX = findItemInRow(saveId, y, withButtons);
    ASSERT_GE(saveX, 0.0f) << "the Save button was never hovered";

    // Save: the file holds the points and names the TF after itself.
    std::filesystem::remove(dir / "my_ct.json");
    state.tfFile = (dir / "my_ct.json").string();
    state.tfEdited = true;
    click(saveX, y, withButtons);
    ASSERT_TRUE(state.errorMessage.empty()) << state.errorMessage;
    const TransferFunction saved = renderer::loadTransferFunction(dir / "my_ct.json");
    ASSERT_EQ(saved.opacities.size(), 3u);
    EXPECT_FALSE(saved.windowFractions);
    EXPECT_EQ(saved.opacities[1].value, 1000.0);   // data units, not 0.5 of the window
    EXPECT_EQ(saved.colours[1].colour, glm::dvec3(1, 0, 0));
    EXPECT_EQ(saved.name, "my_ct");
    EXPECT_EQ(state.tf.name, "my_ct");
    EXPECT_FALSE(state.tfEdited);

    // Load replaces the curve.
    state.tf = renderer::builtinPreset("fire");
    changed = false;
    click(20.0f, y, withButtons);
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf.opacities.size(), 3u);
    EXPECT_EQ(state.tf.name, "my_ct");

    // A broken file: the error names it, the curve stays.
    std::ofstream(dir / "broken_tf.json") << "{\"points\": [";
    state.tfFile = (dir / "broken_tf.json").string();
    changed = false;
    click(20.0f, y, withButtons);
    EXPECT_THAT(state.errorMessage, HasSubstr("broken_tf.json"));
    EXPECT_THAT(state.errorMessage, HasSubstr("not valid JSON"));
    EXPECT_FALSE(changed);
    EXPECT_EQ(state.tf.name, "my_ct");

    // Saving where no folder is: the error names the file, the TF keeps its name.
    state.errorMessage.clear();
    state.tfFile = (dir / "no_such_folder" / "x.json").string();
    click(saveX, y, withButtons);
    EXPECT_THAT(state.errorMessage, HasSubstr("no_such_folder"));
    EXPECT_EQ(state.tf.name, "my_ct");
}

TEST_F(TfPanel, PickingAPresetReplacesTheCurveAndClearsTheSelection) {
    state.tfSelected = 2;
    ASSERT_TRUE(pickPreset("fire"));
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf.name, "fire");
    EXPECT_EQ(state.tf, renderer::inDataUnits(renderer::builtinPreset("fire"), window));   // fixed over the window
    EXPECT_EQ(state.tfSelected, -1);
}

TEST_F(TfPanel, ThePresetListOffersTheBundledPresetFilesToo) {
    ASSERT_TRUE(pickPreset("bonsai")) << "assets/presets/bonsai.json is not in the list";
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf, renderer::inDataUnits(
                            renderer::loadTransferFunction(testing_support::assetDir() / "presets" / "bonsai.json"),
                            window));
}

TEST_F(TfPanel, TheValueProbedInTheViewportIsMarkedOnTheAxis) {
    const Rect canvas = findCanvas();
    // The x of every vertex drawn in the marker's colour in the last frame.
    auto markerXs = [] {
        std::vector<float> xs;
        const ImDrawData* data = ImGui::GetDrawData();
        for (int l = 0; l < data->CmdListsCount; ++l)
            for (const ImDrawVert& v : data->CmdLists[l]->VtxBuffer)
                if (v.col == ui::kProbeMarkerColour) xs.push_back(v.pos.x);
        return xs;
    };
    mouse(1000, 1000, false);
    frame(body());
    EXPECT_TRUE(markerXs().empty()) << "nothing probed";
    state.probe = ui::EditorState::ProbedVoxel{{1, 2, 3}, 1400.0f};   // 0.6 of the window -1000 .. 3000
    frame(body());
    const std::vector<float> xs = markerXs();
    ASSERT_FALSE(xs.empty());
    const float expected = ui::tfToCanvas(canvas, 0.6, 0.0).x;
    for (float x : xs) EXPECT_NEAR(x, expected, 1.5f);
    state.probe->value = 5000.0f;   // beyond the window: off the axis, no mark
    frame(body());
    EXPECT_TRUE(markerXs().empty());
}

TEST_F(TfPanel, ADragIsOneUndoStepAndCtrlZCtrlYWalkTheHistory) {
    const Rect canvas = findCanvas();
    const TransferFunction before = state.tf;
    const CanvasPoint at = ui::tfToCanvas(canvas, 0.5, 0.5);
    press(at, 0);
    for (int i = 1; i <= 5; ++i) press({at.x + 4.0f * float(i), at.y - 3.0f * float(i)}, 0);   // one drag
    release(0);
    const TransferFunction dragged = state.tf;
    ASSERT_NE(dragged, before);
    ASSERT_EQ(state.tfHistory.undo.size(), 1u) << "a drag of 5 moves must be one step";

    // Ctrl+Z: back to before the drag; Ctrl+Y: the drag again. (ImGui 1.86's legacy key map.)
    ImGuiIO& io = ImGui::GetIO();
    io.KeyMap[ImGuiKey_Z] = 'Z';
    io.KeyMap[ImGuiKey_Y] = 'Y';
    auto chord = [&](int key) {
        io.KeyCtrl = true;
        io.KeysDown[key] = true;
        frame(body());
        io.KeysDown[key] = false;
        io.KeyCtrl = false;
        frame(body());
    };
    changed = false;
    chord('Z');
    EXPECT_EQ(state.tf, before);
    EXPECT_TRUE(changed);
    chord('Y');
    EXPECT_EQ(state.tf, dragged);
    chord('Z');
    EXPECT_EQ(state.tf, before);
    EXPECT_TRUE(state.tfHistory.undo.empty());
    chord('Z');   // nothing more to undo
    EXPECT_EQ(state.tf, before);
}

// ParaView's Color Map Editor: the colour bar's stops under the curve. Dragging a stop moves that colour
// stop only; every opacity point stays, and dragging an opacity point leaves every colour stop.
TEST_F(TfPanel, DraggingAColourStopLeavesOpacityAloneAndTheReverse) {
    const Rect canvas = findCanvas();
    const Rect bar = findColourBar(canvas);
    ASSERT_GT(bar.h, 5.0f) << "no colour bar under the canvas";
    const TransferFunction before = state.tf;
    // The middle stop (1000, half the window), grabbed in the bar's lower half where its marker is.
    const float x = bar.x + 0.5f * bar.w, y = bar.bottom() - 3.0f;
    press({x + 2, y}, 0);
    EXPECT_EQ(state.tfColourSelected, 1);
    EXPECT_EQ(state.tfSelected, -1);
    EXPECT_EQ(state.tf.colours.size(), 3u) << "pressing on a stop added one";
    press({x + 2 + 0.2f * bar.w, y - 20.0f}, 0);   // up and right: only across counts
    release(0);
    EXPECT_TRUE(changed);
    EXPECT_NEAR(state.tf.colours[1].value, data(0.7), pixel(bar));
    EXPECT_EQ(state.tf.colours[1].colour, before.colours[1].colour);
    EXPECT_EQ(state.tf.opacities, before.opacities) << "a colour stop's drag moved opacity";

    // The reverse: the middle opacity point dragged; the colour stops stay where they now are.
    const TransferFunction colouredBefore = state.tf;
    changed = false;
    const CanvasPoint at = ui::tfToCanvas(canvas, 0.5, 0.5);
    press(at, 0);
    ASSERT_EQ(state.tfSelected, 1);
    EXPECT_EQ(state.tfColourSelected, -1);
    press({at.x - 0.2f * canvas.w, at.y + 0.2f * canvas.h}, 0);
    release(0);
    EXPECT_TRUE(changed);
    EXPECT_NEAR(state.tf.opacities[1].value, data(0.3), pixel(canvas));
    EXPECT_EQ(state.tf.colours, colouredBefore.colours) << "an opacity point's drag moved a colour stop";

    // A click on empty bar adds a stop with the colour already there; right-click removes it.
    changed = false;
    const double at25 = data(0.25);
    const glm::dvec3 colourThere(renderer::evaluate(state.tf, at25));
    press({bar.x + 0.25f * bar.w, y}, 0);
    release(0);
    ASSERT_EQ(state.tf.colours.size(), 4u);
    EXPECT_TRUE(changed);
    EXPECT_NEAR(state.tf.colours[1].value, at25, pixel(bar));
    EXPECT_NEAR(glm::length(state.tf.colours[1].colour - colourThere), 0.0, 2e-3);
    const auto opacities = state.tf.opacities;
    press({bar.x + 0.25f * bar.w, y}, 1);
    release(1);
    EXPECT_EQ(state.tf.colours.size(), 3u);
    EXPECT_EQ(state.tf.opacities, opacities);
}

// Shift drags every point by one offset; Rescale's buttons map the points' span onto the data range, the
// window, p1..p99 or the visible range, as the pure functions do.
TEST_F(TfPanel, ShiftAndRescaleActOnTheWholeTf) {
    ImGuiID shiftId = 0, dataId = 0, windowId = 0, percentileId = 0, visibleId = 0;
    auto withIds = [&] {
        shiftId = ImGui::GetID("Shift");
        dataId = ImGui::GetID("data");
        windowId = ImGui::GetID("window");
        percentileId = ImGui::GetID("1-99 %");
        visibleId = ImGui::GetID("visible");
        draw();
    };
    frame(withIds);
    const float shiftY = findItem(shiftId, 60.0f, 0.0f, 800.0f, withIds);
    ASSERT_GE(shiftY, 0.0f) << "no Shift field";
    const TransferFunction before = state.tf;
    // Drag Shift 30 px right: every point moves by the same positive offset, nothing else changes.
    mouse(60.0f, shiftY, true);
    frame(withIds);
    for (int step = 1; step <= 6; ++step) {
        mouse(60.0f + 5.0f * float(step), shiftY, true);
        frame(withIds);
    }
    mouse(90.0f, shiftY, false);
    frame(withIds);
    EXPECT_TRUE(changed);
    const double offset = state.tf.opacities[0].value - before.opacities[0].value;
    EXPECT_GT(offset, 0.0);
    EXPECT_EQ(state.tf, renderer::shifted(before, offset));
    EXPECT_EQ(state.tfShift, 0.0) << "the field keeps an offset after the drag";

    // Each Rescale button: the points' span becomes its range.
    const float rowY = [&] {
        for (float y = shiftY; y < shiftY + 120.0f; y += 2.0f)
            if (findItemInRow(dataId, y, withIds) >= 0.0f) return y;
        return -1.0f;
    }();
    ASSERT_GE(rowY, 0.0f) << "no Rescale buttons below Shift";
    const std::pair<ImGuiID*, renderer::ValueRange> buttons[] = {
        {&dataId, view.dataRange}, {&windowId, window}, {&percentileId, view.percentile}, {&visibleId, view.visible}};
    for (const auto& [id, range] : buttons) {
        const float x = findItemInRow(*id, rowY, withIds);
        ASSERT_GE(x, 0.0f);
        const TransferFunction was = state.tf;
        changed = false;
        click(x, rowY, withIds);
        EXPECT_TRUE(changed);
        EXPECT_EQ(state.tf, renderer::rescaled(was, range.lo, range.hi));
        EXPECT_EQ(renderer::extentOf(state.tf).lo, double(range.lo));
        EXPECT_EQ(renderer::extentOf(state.tf).hi, double(range.hi));
    }
}

// A built-in preset (window fractions) is fixed in data units over the window it is first shown with: a
// later window change leaves it where it is over the data.
TEST_F(TfPanel, AWindowFractionTfIsFixedInDataUnitsWhenShown) {
    state.tf = renderer::builtinPreset("ct-bone");
    frame(body());
    EXPECT_TRUE(changed);
    EXPECT_FALSE(state.tf.windowFractions);
    EXPECT_EQ(state.tf, renderer::inDataUnits(renderer::builtinPreset("ct-bone"), window));
    const TransferFunction fixed = state.tf;
    view.window = {0.0f, 500.0f};
    frame(body());
    EXPECT_EQ(state.tf, fixed);
}
