// The Transfer function panel's gradient opacity curve: its edit rules, and mouse input on the curve
// changing the TF and, through the scene it is baked into, the image.
#include "imgui_null.h"
#include "ui/gradient_opacity_curve.h"

#include "renderer/math/metrics.h"
#include "renderer/model/gradients.h"
#include "renderer/model/procedural.h"
#include "renderer/model/splat_scene.h"
#include "renderer/oracle/reference_renderer.h"

#include <gtest/gtest.h>

using renderer::TransferFunction;
using ui::CanvasPoint;
using ui::Rect;

namespace {

TransferFunction ramp() {
    return renderer::fromSharedPoints("ramp", {{0.0, {0.9, 0.8, 0.7}, 0.0},
                                               {0.4, {0.9, 0.8, 0.7}, 0.0},
                                               {0.6, {1.0, 0.9, 0.8}, 0.8},
                                               {1.0, {1.0, 1.0, 1.0}, 1.0}});
}

} // namespace

TEST(GradientCurve, TheFirstPointKeepsAFactorOfOneElsewhereAndPointsStaySorted) {
    TransferFunction tf;
    EXPECT_EQ(ui::insertGradientPoint(tf, 20.0, 0.0, 100.0), 1);
    ASSERT_EQ(tf.gradientOpacity.size(), 3u);
    EXPECT_EQ(renderer::evaluateGradientOpacity(tf, 0.0), 1.0);
    EXPECT_EQ(renderer::evaluateGradientOpacity(tf, 20.0), 0.0);
    EXPECT_EQ(renderer::evaluateGradientOpacity(tf, 100.0), 1.0);
    ui::moveGradientPoint(tf, 1, 500.0, 2.0); // past its neighbour and the top: held at both
    EXPECT_EQ(tf.gradientOpacity[1].magnitude, 100.0);
    EXPECT_EQ(tf.gradientOpacity[1].opacity, 1.0);
    for (int i = 2; i >= 0; --i)
        EXPECT_TRUE(ui::removeGradientPoint(tf, i));
    EXPECT_TRUE(tf.gradientOpacity.empty()) << "no points: no gradient opacity";
    EXPECT_FALSE(ui::removeGradientPoint(tf, 0));
}

TEST(GradientCurve, TheAxisIsTheMagnitudeBytesAndRoundTrips) {
    const Rect canvas{10, 20, 200, 80};
    const CanvasPoint p = ui::gradientToCanvas(canvas, 25.0, 0.5, 100.0);
    EXPECT_FLOAT_EQ(p.x, 10.0f + 0.5f * 200.0f) << "sqrt(25 / 100) across";
    double magnitude = 0, factor = 0;
    ui::canvasToGradient(canvas, p, 100.0, magnitude, factor);
    EXPECT_NEAR(magnitude, 25.0, 1e-9);
    EXPECT_NEAR(factor, 0.5, 1e-6);
}

namespace {

class GradientCurvePanel : public ImGuiNull {
  protected:
    TransferFunction tf = ramp();
    ui::GradientCurveEdit edit;
    std::vector<uint64_t> histogram = std::vector<uint64_t>(renderer::kGradientBins, 10);
    ui::GradientCurveView view{.maxMagnitude = 4.0, .histogram = &histogram};
    bool changed = false;
    ImGuiID canvasId = 0;

    std::function<void()> body() {
        return [this] {
            ImGui::SetNextItemOpen(true, ImGuiCond_Once); // the section starts collapsed
            canvasId = ImGui::GetID("##gradient_canvas");
            changed |= ui::drawGradientOpacityCurve(tf, edit, view);
        };
    }
    Rect findCanvas() { return findItemRect(canvasId, 300, body()); }
    void press(CanvasPoint p) {
        mouse(p.x, p.y, true);
        frame(body());
    }
    void release() {
        ImGui::GetIO().MouseDown[0] = false;
        frame(body());
    }
};

} // namespace

TEST_F(GradientCurvePanel, ClickingAndDraggingTheCurveChangesTheTfAndTheImage) {
    const Rect canvas = findCanvas();
    ASSERT_GT(canvas.w, 100.0f);
    ASSERT_GT(canvas.h, 30.0f);
    EXPECT_FALSE(changed);
    // A click on the curve (flat at 1 without points), a third across: a point there, and the ends at
    // factor 1 around it.
    press(ui::gradientToCanvas(canvas, view.maxMagnitude / 9.0, 1.0, view.maxMagnitude));
    release();
    EXPECT_TRUE(changed);
    ASSERT_EQ(tf.gradientOpacity.size(), 3u);
    // Drag the new point to the baseline: weak gradients fade out.
    const auto p = tf.gradientOpacity[size_t(edit.selected)];
    const CanvasPoint at = ui::gradientToCanvas(canvas, p.magnitude, p.opacity, view.maxMagnitude);
    press(at);
    press({at.x + 0.2f * canvas.w, canvas.bottom()});
    release();
    const auto& moved = tf.gradientOpacity[size_t(edit.selected)];
    EXPECT_EQ(moved.opacity, 0.0) << "the baseline snaps to 0";
    EXPECT_NEAR(std::sqrt(moved.magnitude / view.maxMagnitude),
                double(at.x + 0.2f * canvas.w - canvas.x) / canvas.w, 1.5 / canvas.w);

    // The image: the same scene, baked with the TF before and after the edit.
    const renderer::Volume volume = renderer::makeMarschnerLobb(12);
    renderer::SplatScene scene = renderer::buildSplatScene(volume, ramp());
    renderer::addGradients(scene, *renderer::computeGradients(volume));
    const renderer::ImagePlane plane =
        renderer::makeImagePlane(renderer::Camera{}, scene.centre, scene.radius, 24, 24);
    const renderer::Image before = renderer::renderReference(scene, plane, {});
    renderer::setTransferFunction(scene, tf);
    EXPECT_GT(renderer::compareImages(renderer::renderReference(scene, plane, {}), before).rmse, 1e-3);

    // Right-click removes a point; "None" (not clicked here) would clear them all.
    changed = false;
    const CanvasPoint now = ui::gradientToCanvas(canvas, moved.magnitude, moved.opacity, view.maxMagnitude);
    ImGui::GetIO().MousePos = ImVec2(now.x, now.y - 2.0f); // on the baseline: just inside the canvas
    ImGui::GetIO().MouseDown[1] = true;
    frame(body());
    ImGui::GetIO().MouseDown[1] = false;
    frame(body());
    EXPECT_TRUE(changed);
    EXPECT_EQ(tf.gradientOpacity.size(), 2u);
}

TEST_F(GradientCurvePanel, WithoutGradientsTheSectionWaitsAndEditsNothing) {
    view.maxMagnitude = 0.0;
    const std::string text = loggedText(body());
    EXPECT_NE(text.find("Waits for the volume's gradients"), std::string::npos) << text;
    EXPECT_FALSE(changed);
}
