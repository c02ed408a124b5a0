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

using renderer::ControlPoint;
using renderer::TransferFunction;
using testing::HasSubstr;
using ui::CanvasPoint;
using ui::Rect;

TransferFunction threePoints() {
    return {"three", {{0.0, {0, 0, 0}, 0.0}, {0.5, {1, 0, 0}, 0.5}, {1.0, {1, 1, 1}, 1.0}}};
}

bool sorted(const TransferFunction& tf) {
    for (size_t i = 1; i < tf.points.size(); ++i)
        if (tf.points[i].value < tf.points[i - 1].value) return false;
    return true;
}

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
        const renderer::Lut before = renderer::bakeLut(tf);
        const int i = ui::insertControlPoint(tf, v, renderer::evaluate(tf, v).a);
        ASSERT_EQ(tf.points.size(), 4u);
        EXPECT_EQ(tf.points[size_t(i)].value, v);
        EXPECT_TRUE(sorted(tf));
        const renderer::Lut after = renderer::bakeLut(tf);
        double worst = 0;
        for (size_t k = 0; k < before.size(); ++k)
            for (int c = 0; c < 4; ++c) worst = std::max(worst, double(std::abs(after[k][c] - before[k][c])));
        EXPECT_LT(worst, 1e-6) << "inserting at " << v << " changed the table";
    }
    // Off the curve, only the two intervals around the new point change.
    TransferFunction tf = threePoints();
    const renderer::Lut before = renderer::bakeLut(tf);
    ui::insertControlPoint(tf, 0.25, 0.9);
    const renderer::Lut after = renderer::bakeLut(tf);
    for (size_t k = renderer::kLutSize / 2; k < before.size(); ++k) ASSERT_EQ(after[k], before[k]) << k;
    EXPECT_NEAR(after[renderer::kLutSize / 4].a, 0.9, 1e-3);
}

TEST(TfCurve, ADraggedPointStaysBetweenItsNeighboursAndInsideTheSquare) {
    TransferFunction tf = threePoints();
    ui::moveControlPoint(tf, 1, 0.9, 2.0);
    EXPECT_EQ(tf.points[1].value, 0.9);
    EXPECT_EQ(tf.points[1].opacity, 1.0);
    ui::moveControlPoint(tf, 1, 1.5, -1.0);   // past the last point
    EXPECT_EQ(tf.points[1].value, 1.0);
    EXPECT_EQ(tf.points[1].opacity, 0.0);
    ui::moveControlPoint(tf, 1, -3.0, 0.4);   // past the first
    EXPECT_EQ(tf.points[1].value, 0.0);
    ui::moveControlPoint(tf, 0, 0.6, 0.2);    // the first point stops at its right neighbour
    EXPECT_EQ(tf.points[0].value, 0.0);
    ui::moveControlPoint(tf, 1, std::nan(""), 0.7);   // NaN keeps that coordinate
    EXPECT_EQ(tf.points[1].value, 0.0);
    EXPECT_EQ(tf.points[1].opacity, 0.7);
    ui::moveControlPoint(tf, 7, 0.5, 0.5);    // no such point: nothing happens
    ui::moveControlPoint(tf, -1, 0.5, 0.5);
    EXPECT_TRUE(sorted(tf));
    EXPECT_EQ(tf.points.size(), 3u);
}

TEST(TfCurve, RemovingKeepsAStartAndAnEnd) {
    TransferFunction tf = threePoints();
    EXPECT_FALSE(ui::removeControlPoint(tf, 3));
    EXPECT_FALSE(ui::removeControlPoint(tf, -1));
    EXPECT_TRUE(ui::removeControlPoint(tf, 1));
    EXPECT_EQ(tf.points.size(), 2u);
    EXPECT_FALSE(ui::removeControlPoint(tf, 0));
    EXPECT_EQ(tf.points.size(), 2u);
}

TEST(TfCurve, PickingFindsTheNearestPointWithinTheRadius) {
    const Rect canvas{0, 0, 200, 100};
    TransferFunction tf = threePoints();   // points at (0, 100), (100, 50), (200, 0)
    EXPECT_EQ(ui::pickControlPoint(tf, canvas, {104, 47}, 8), 1);
    EXPECT_EQ(ui::pickControlPoint(tf, canvas, {120, 50}, 8), -1);
    EXPECT_EQ(ui::pickControlPoint(tf, canvas, {3, 98}, 8), 0);
    ui::insertControlPoint(tf, 0.52, 0.5);   // two points 4 px apart: the nearer wins
    EXPECT_EQ(ui::pickControlPoint(tf, canvas, {103, 50}, 8), 2);
    EXPECT_EQ(ui::pickControlPoint(tf, canvas, {99, 50}, 8), 1);
}

TEST(TfCurve, HistoryUndoesAndRedoesAndForgetsRedoOnANewEdit) {
    ui::TfHistory h;
    TransferFunction tf = threePoints();
    EXPECT_FALSE(h.undoInto(tf));
    const TransferFunction a = tf;
    h.record(tf);
    ui::moveControlPoint(tf, 1, 0.7, 0.2);
    const TransferFunction b = tf;
    h.record(tf);
    ui::removeControlPoint(tf, 1);
    ASSERT_TRUE(h.undoInto(tf));
    EXPECT_EQ(tf, b);
    ASSERT_TRUE(h.undoInto(tf));
    EXPECT_EQ(tf, a);
    EXPECT_FALSE(h.undoInto(tf));
    ASSERT_TRUE(h.redoInto(tf));
    EXPECT_EQ(tf, b);
    h.record(tf);   // a new edit: the redone-away future is gone
    ui::insertControlPoint(tf, 0.1, 0.1);
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
    bool changed = false;
    ImGuiID canvasId = 0;

    void SetUp() override {
        ImGuiNull::SetUp();
        state.tf = threePoints();
    }
    void draw() {
        canvasId = ImGui::GetID("##tf_canvas");
        changed |= ui::drawTransferFunctionPanel(state, {.histogram = nullptr, .window = window});
    }
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
    // The canvas's rectangle, found by hovering: its first and last hovered pixels across and down.
    Rect findCanvas() {
        frame(body());
        float top = -1, bottom = -1, left = -1, right = -1;
        for (float y = 0; y < 700; y += 1) {
            mouse(200, y, false);
            frame(body());
            if (ImGui::GetCurrentContext()->HoveredId == canvasId) (top < 0 ? top : bottom) = y;
        }
        const float mid = (top + bottom) * 0.5f;
        for (float x = 0; x < 400; x += 1) {
            mouse(x, mid, false);
            frame(body());
            if (ImGui::GetCurrentContext()->HoveredId == canvasId) (left < 0 ? left : right) = x;
        }
        return {left, top, right + 1 - left, bottom + 1 - top};
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
    EXPECT_EQ(state.tf.points.size(), 3u) << "pressing on a point added one";
    EXPECT_FALSE(changed) << "a press without motion changed the TF";
    press({at.x + 3 + 0.2f * canvas.w, at.y - 2 - 0.1f * canvas.h}, 0);
    release(0);
    EXPECT_TRUE(changed);
    EXPECT_TRUE(state.tfEdited);
    // ImGui floors the mouse position: a pixel either way.
    EXPECT_NEAR(state.tf.points[1].value, 0.7, 1.0 / canvas.w);
    EXPECT_NEAR(state.tf.points[1].opacity, 0.6, 1.0 / canvas.h);
    // Dragged far past the last point, it stops there.
    const CanvasPoint now = ui::tfToCanvas(canvas, state.tf.points[1].value, state.tf.points[1].opacity);
    press(now, 0);
    press({now.x + canvas.w, now.y}, 0);
    release(0);
    EXPECT_EQ(state.tf.points[1].value, 1.0);
    EXPECT_TRUE(sorted(state.tf));
}

TEST_F(TfPanel, ClickingEmptySpaceAddsAPointAndRightClickingRemovesIt) {
    const Rect canvas = findCanvas();
    const TransferFunction before = state.tf;
    const CanvasPoint spot = ui::tfToCanvas(canvas, 0.25, 0.8);
    press(spot, 0);
    release(0);
    ASSERT_EQ(state.tf.points.size(), 4u);
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tfSelected, 1);
    const ControlPoint& added = state.tf.points[1];
    EXPECT_NEAR(added.value, 0.25, 1.0 / canvas.w);
    EXPECT_NEAR(added.opacity, 0.8, 1.0 / canvas.h);
    const glm::dvec3 expected(renderer::evaluate(before, added.value));   // the colour the curve had there
    EXPECT_NEAR(glm::length(added.colour - expected), 0.0, 1e-12);

    changed = false;
    press(ui::tfToCanvas(canvas, 0.6, 0.95), 1);   // right-click on empty space: nothing
    release(1);
    EXPECT_EQ(state.tf.points.size(), 4u);
    EXPECT_FALSE(changed);
    press(ui::tfToCanvas(canvas, added.value, added.opacity), 1);
    release(1);
    EXPECT_EQ(state.tf.points.size(), 3u);
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
    ASSERT_EQ(saved.points.size(), 3u);
    EXPECT_EQ(saved.points[1].value, 0.5);
    EXPECT_EQ(saved.points[1].colour, glm::dvec3(1, 0, 0));
    EXPECT_EQ(saved.name, "my_ct");
    EXPECT_EQ(state.tf.name, "my_ct");
    EXPECT_FALSE(state.tfEdited);

    // Load replaces the curve.
    state.tf = renderer::builtinPreset("fire");
    changed = false;
    click(20.0f, y, withButtons);
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf.points.size(), 3u);
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
    EXPECT_EQ(state.tf.points.size(), renderer::builtinPreset("fire").points.size());
    EXPECT_EQ(state.tfSelected, -1);
}

TEST_F(TfPanel, ThePresetListOffersTheBundledPresetFilesToo) {
    ASSERT_TRUE(pickPreset("bonsai")) << "assets/presets/bonsai.json is not in the list";
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf, renderer::loadTransferFunction(testing_support::assetDir() / "presets" / "bonsai.json"));
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
