// The Transfer function panel's 2D section: its edit rules (pure), and synthetic mouse input through the
// whole panel adding, dragging, resizing and removing widgets, a gesture an undo step.
#include "imgui_null.h"
#include "ui/panels.h"
#include "ui/tf2d_editor.h"

#include "renderer/model/splat_scene.h"

#include <gtest/gtest.h>

using renderer::TransferFunction;
using renderer::Widget2D;
using renderer::WidgetShape;
using ui::CanvasPoint;
using ui::Rect;
using ui::WidgetHandle;

namespace {

const ui::Tf2dAxes kAxes{.window = {-1000.0f, 3000.0f}, .maxMagnitude = 400.0};

TransferFunction oneRectangle() {
    TransferFunction tf = renderer::inDataUnits(
        renderer::fromSharedPoints("ramp", {{0.0, {0, 0, 0}, 0.0}, {1.0, {1, 1, 1}, 1.0}}), kAxes.window);
    ui::addRectangle(tf, kAxes);
    return tf;
}

} // namespace

TEST(Tf2dEditor, TheAxesRoundTripOnTheMagnitudeBytesSqrtScale) {
    const Rect canvas{10, 20, 400, 100};
    const CanvasPoint p = ui::tf2dToCanvas(canvas, kAxes, 1000.0, 100.0);
    EXPECT_FLOAT_EQ(p.x, 10.0f + 0.5f * 400.0f);
    EXPECT_FLOAT_EQ(p.y, 120.0f - 0.5f * 100.0f) << "sqrt(100 / 400) up";
    double value = 0, magnitude = 0;
    ui::canvasToTf2d(canvas, kAxes, p, value, magnitude);
    EXPECT_NEAR(value, 1000.0, 1e-9);
    EXPECT_NEAR(magnitude, 100.0, 1e-9);
}

TEST(Tf2dEditor, HandlesPickBeforeBodiesAndDragsFollowThePointer) {
    const Rect canvas{0, 0, 400, 100};
    TransferFunction tf = oneRectangle();
    const int t = ui::addTriangle(tf, kAxes);
    ASSERT_EQ(t, 1);
    const Widget2D& rect = tf.widgets2d[0];
    const Widget2D& tri = tf.widgets2d[1];
    EXPECT_NE(rect.colour, tri.colour) << "each new widget its own colour";
    // The rectangle's top-right corner, its middle, the triangle's top corner, empty space.
    const CanvasPoint corner = ui::tf2dToCanvas(canvas, kAxes, rect.valueHi, rect.magnitudeHi);
    const ui::WidgetPick pc = ui::pickWidget(tf, canvas, kAxes, {corner.x + 2, corner.y + 1}, 7.0f);
    EXPECT_EQ(pc.index, 0);
    EXPECT_EQ(pc.handle, WidgetHandle::HighHigh);
    const CanvasPoint top = ui::tf2dToCanvas(canvas, kAxes, tri.apex + tri.halfWidth, tri.magnitudeTop);
    EXPECT_EQ(ui::pickWidget(tf, canvas, kAxes, top, 7.0f).handle, WidgetHandle::TopRight);
    const CanvasPoint inside = ui::tf2dToCanvas(canvas, kAxes, tri.apex, 0.5 * tri.magnitudeTop);
    EXPECT_EQ(ui::pickWidget(tf, canvas, kAxes, inside, 7.0f).handle, WidgetHandle::Body);
    EXPECT_EQ(ui::pickWidget(tf, canvas, kAxes, {2, 2}, 7.0f).index, -1);

    // A corner drag puts that corner under the pointer; the opposite one stays; crossing swaps them.
    Widget2D w = ui::draggedWidget(rect, WidgetHandle::HighHigh, canvas, kAxes, corner, {corner.x + 40, 0});
    EXPECT_NEAR(w.valueHi, rect.valueHi + 40.0 / 400.0 * 4000.0, 1e-6);
    EXPECT_NEAR(w.magnitudeHi, 400.0, 1e-9);
    EXPECT_EQ(w.valueLo, rect.valueLo);
    EXPECT_EQ(w.magnitudeLo, rect.magnitudeLo);
    w = ui::draggedWidget(rect, WidgetHandle::HighHigh, canvas, kAxes, corner, {0, 100});
    EXPECT_NEAR(w.valueLo, -1000.0, 1e-6);
    EXPECT_EQ(w.valueHi, rect.valueLo);
    EXPECT_EQ(w.magnitudeLo, 0.0);
    EXPECT_EQ(w.magnitudeHi, rect.magnitudeLo);
    // The body moves both corners by the pointer's pixels and keeps its height on the canvas.
    w = ui::draggedWidget(rect, WidgetHandle::Body, canvas, kAxes, {200, 50}, {180, 60});
    EXPECT_NEAR(w.valueLo, rect.valueLo - 200.0, 1e-6);
    EXPECT_NEAR(w.valueHi, rect.valueHi - 200.0, 1e-6);
    EXPECT_NEAR(ui::tf2dToCanvas(canvas, kAxes, 0, w.magnitudeLo).y,
                ui::tf2dToCanvas(canvas, kAxes, 0, rect.magnitudeLo).y + 10.0f, 1e-3);
    // A triangle's apex stays at magnitude 0; its top corner sets the width and the top.
    w = ui::draggedWidget(tri, WidgetHandle::Body, canvas, kAxes, inside, {inside.x + 10, inside.y - 30});
    EXPECT_NEAR(w.apex, tri.apex + 100.0, 1e-6);
    EXPECT_EQ(w.magnitudeTop, tri.magnitudeTop);
    w = ui::draggedWidget(tri, WidgetHandle::TopRight, canvas, kAxes, top, {top.x + 20, top.y - 20});
    EXPECT_NEAR(w.halfWidth, tri.halfWidth + 200.0, 1e-6);
    EXPECT_NEAR(w.magnitudeTop, 400.0 * 0.7 * 0.7, 1e-6);
    EXPECT_EQ(w.apex, tri.apex);
    w = ui::draggedWidget(tri, WidgetHandle::TopEdge, canvas, kAxes, top, {top.x, 200});   // below the canvas
    EXPECT_GT(w.magnitudeTop, 0.0) << "a triangle keeps a top";
    EXPECT_EQ(w.halfWidth, tri.halfWidth);
    EXPECT_TRUE(ui::removeWidget(tf, 0));
    EXPECT_EQ(tf.widgets2d.size(), 1u);
    EXPECT_FALSE(ui::removeWidget(tf, 3));
}

// == Through the panel

namespace {

class Tf2dPanel : public ImGuiNull {
  protected:
    ui::EditorState state;
    std::vector<uint32_t> histogram = std::vector<uint32_t>(renderer::kTf2dCells, 5);
    ui::TransferFunctionView view = [this] {
        ui::TransferFunctionView v;
        v.window = kAxes.window, v.dataRange = kAxes.window, v.percentile = kAxes.window, v.visible = kAxes.window;
        v.gradients.maxMagnitude = kAxes.maxMagnitude;
        v.histogram2d = &histogram;
        v.histogram2dWindow = kAxes.window;
        return v;
    }();
    bool changed = false;
    ImGuiID canvasId = 0;

    void SetUp() override {
        ImGuiNull::SetUp();
        ImGui::GetIO().DisplaySize = ImVec2(1280, 1600);
        windowHeight = 1500;
        state.tf = oneRectangle();   // with a widget the section starts open
    }
    std::function<void()> body() {
        return [this] {
            canvasId = ImGui::GetID("##tf2d_canvas");
            changed |= ui::drawTransferFunctionPanel(state, view);
        };
    }
    void press(CanvasPoint p, int button = 0) {
        ImGui::GetIO().MousePos = ImVec2(p.x, p.y);
        ImGui::GetIO().MouseDown[button] = true;
        frame(body());
    }
    void release(int button = 0) {
        ImGui::GetIO().MouseDown[button] = false;
        frame(body());
    }
    void drag(CanvasPoint from, CanvasPoint to) {
        press(from);
        for (int i = 1; i <= 4; ++i)
            press({from.x + (to.x - from.x) * float(i) / 4.0f, from.y + (to.y - from.y) * float(i) / 4.0f});
        release();
    }
};

} // namespace

TEST_F(Tf2dPanel, AddingDraggingAndResizingWidgetsFollowsThePointerAGestureAnUndoStep) {
    const Rect canvas = findItemRect(canvasId, 1500, body());
    ASSERT_GT(canvas.w, 200.0f);
    ASSERT_GT(canvas.h, 60.0f);
    const double perPixel = 4000.0 / canvas.w;

    // Drag the rectangle's body 30 px right and 10 px up: its values move by 30 px, in one undo step.
    const Widget2D before = state.tf.widgets2d[0];
    const CanvasPoint middle = ui::tf2dToCanvas(canvas, kAxes, 0.5 * (before.valueLo + before.valueHi),
                                                0.5 * (before.magnitudeLo + before.magnitudeHi));
    changed = false;
    drag(middle, {middle.x + 30.0f, middle.y - 10.0f});
    EXPECT_TRUE(changed);
    const Widget2D moved = state.tf.widgets2d[0];
    EXPECT_NEAR(moved.valueLo, before.valueLo + 30.0 * perPixel, 0.01 * perPixel);
    EXPECT_NEAR(moved.valueHi - moved.valueLo, before.valueHi - before.valueLo, 1e-6);
    EXPECT_GT(moved.magnitudeLo, before.magnitudeLo);
    EXPECT_EQ(state.tf2d.selected, 0);
    ASSERT_EQ(state.tfHistory.undo.size(), 1u) << "a drag of several moves must be one step";

    // Resize by its low-value, low-magnitude corner: that corner goes where the pointer goes.
    const CanvasPoint corner = ui::tf2dToCanvas(canvas, kAxes, moved.valueLo, moved.magnitudeLo);
    drag(corner, {corner.x - 50.0f, canvas.bottom() - 1.0f});
    const Widget2D resized = state.tf.widgets2d[0];
    EXPECT_NEAR(resized.valueLo, moved.valueLo - 50.0 * perPixel, 0.01 * perPixel);   // to float pixels
    EXPECT_EQ(resized.valueHi, moved.valueHi);
    EXPECT_LT(resized.magnitudeLo, moved.magnitudeLo);
    EXPECT_EQ(resized.magnitudeHi, moved.magnitudeHi);
    EXPECT_EQ(state.tfHistory.undo.size(), 2u);

    // "Add triangle": a second widget, selected; its top corner dragged sets its width and top.
    ImGuiID addId = 0;
    const auto withIds = [&] {
        addId = ImGui::GetID("Add triangle");
        body()();
    };
    float y = -1, x = -1;
    for (float yy = canvas.bottom(); yy < canvas.bottom() + 120.0f && x < 0; yy += 3.0f) {
        for (float xx = 5.0f; xx < 390.0f && x < 0; xx += 6.0f) {
            mouse(xx, yy, false);
            frame(withIds);
            if (ImGui::GetCurrentContext()->HoveredId == addId) x = xx, y = yy;
        }
    }
    ASSERT_GE(x, 0.0f) << "no Add triangle button under the canvas";
    click(x, y, withIds);
    ASSERT_EQ(state.tf.widgets2d.size(), 2u);
    EXPECT_EQ(state.tf.widgets2d[1].shape, WidgetShape::Triangle);
    EXPECT_EQ(state.tf2d.selected, 1);
    EXPECT_EQ(state.tfHistory.undo.size(), 3u);
    const Widget2D tri = state.tf.widgets2d[1];
    const CanvasPoint top = ui::tf2dToCanvas(canvas, kAxes, tri.apex + tri.halfWidth, tri.magnitudeTop);
    drag(top, {top.x + 25.0f, top.y});
    EXPECT_NEAR(state.tf.widgets2d[1].halfWidth, tri.halfWidth + 25.0 * perPixel, 0.01 * perPixel);
    EXPECT_NEAR(state.tf.widgets2d[1].magnitudeTop, tri.magnitudeTop, 1e-6 * kAxes.maxMagnitude);

    // Ctrl+Z: the triangle's width back, then no triangle; Ctrl+Y: the triangle again.
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
    chord('Z');
    EXPECT_EQ(state.tf.widgets2d[1], tri);
    chord('Z');
    EXPECT_EQ(state.tf.widgets2d.size(), 1u);
    EXPECT_EQ(state.tf.widgets2d[0], resized);
    chord('Y');
    EXPECT_EQ(state.tf.widgets2d.size(), 2u);

    // Right-click the rectangle (inside its low-magnitude right part, clear of the triangle): removed.
    const CanvasPoint lowRight = ui::tf2dToCanvas(canvas, kAxes, resized.valueHi, resized.magnitudeLo);
    press({lowRight.x - 10.0f, lowRight.y - 10.0f}, 1);
    release(1);
    ASSERT_EQ(state.tf.widgets2d.size(), 1u);
    EXPECT_EQ(state.tf.widgets2d[0].shape, WidgetShape::Triangle);
}

TEST_F(Tf2dPanel, WithoutGradientsTheSectionWaits) {
    view.gradients.maxMagnitude = 0.0;
    const std::string text = loggedText(body());
    EXPECT_NE(text.find("applies once the volume's gradients are computed"), std::string::npos) << text;
}
