// The split view (ui/split_view.h): its pane layout, each pane's settings, the difference pane's figures
// against the project's metric, and the render thread drawing both panes of a request with their own
// settings and |A - B| of exactly those two images.
#include "render_thread.h"
#include "ui/split_view.h"

#include "renderer/errors.h"
#include "renderer/math/metrics.h"
#include "renderer/model/procedural.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

using namespace renderer;

TEST(SplitView, PanesAreEqualSideBySideAndFitTheViewport) {
    const std::vector<ui::PaneRect> three = ui::splitPaneRects(955, 545, 3);
    ASSERT_EQ(three.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(three[i].x, int(i) * 318);
        EXPECT_EQ(three[i].y, 0);
        EXPECT_EQ(three[i].width, 318) << "every pane the same size: they share one image plane";
        EXPECT_EQ(three[i].height, 545);
    }
    EXPECT_LE(three.back().x + three.back().width, 955);
    const std::vector<ui::PaneRect> one = ui::splitPaneRects(955, 545, 1);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0].width, 955);
    EXPECT_EQ(ui::splitPaneRects(1, 0, 2)[1].width, 1) << "a pane is never empty";
    EXPECT_EQ((ui::SplitView{.enabled = true, .difference = true}).paneCount(), 3);
    EXPECT_EQ((ui::SplitView{.enabled = false, .difference = true}).paneCount(), 1);
}

TEST(SplitView, APaneOverridesFilterAndCompositingOnlyAndNeverTilesEverySample) {
    SplatSettings view;
    view.kernelScale = 0.9, view.density = 3.0, view.primitive = SplatSettings::Primitive::Tiles;
    const SplatSettings a = ui::paneSettings(view, {FilterMode::LowPass, Compositing::XRay});
    EXPECT_EQ(a.filter, FilterMode::LowPass);
    EXPECT_EQ(a.compositing, Compositing::XRay);
    EXPECT_EQ(a.primitive, SplatSettings::Primitive::Tiles);
    EXPECT_EQ(a.kernelScale, 0.9);
    EXPECT_EQ(a.density, 3.0);
    const SplatSettings b = ui::paneSettings(view, {FilterMode::Ewa, Compositing::SplatEverySample});
    EXPECT_EQ(b.primitive, SplatSettings::Primitive::Auto) << "tiles sum sheets only";
    EXPECT_EQ(ui::paneLabel({FilterMode::Reconstruction, Compositing::SheetFrontToBack}),
              "reconstruction, sheet-front-to-back");
}

TEST(SplitView, TheScaleTopIsTheNext125StepAndItsColoursRunDarkToLight) {
    EXPECT_DOUBLE_EQ(ui::niceScaleMax(0.03), 0.05);
    EXPECT_DOUBLE_EQ(ui::niceScaleMax(0.1), 0.1);
    EXPECT_DOUBLE_EQ(ui::niceScaleMax(0.11), 0.2);
    EXPECT_DOUBLE_EQ(ui::niceScaleMax(1.5), 2.0);
    EXPECT_DOUBLE_EQ(ui::niceScaleMax(0.0), 1e-6);
    double last = -1.0;
    for (int i = 0; i <= 20; ++i) {
        const auto c = ui::differenceColour(i / 20.0);
        const double luminance = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        EXPECT_GT(luminance, last) << "the scale reads in grey: brighter is larger, at t = " << i / 20.0;
        last = luminance;
    }
}

TEST(SplitView, TheDifferencePaneHasTheMetricsRmseAndColoursEachPixelByItsError) {
    Image a(3, 2), b(3, 2);
    for (size_t i = 0; i < a.rgba.size(); ++i)
        a.rgba[i] = b.rgba[i] = 0.25f;
    b.pixel(1, 0)[0] = 0.25f + 0.08f; // one channel off by 0.08: pixel error 0.04
    for (int c = 0; c < 4; ++c)
        b.pixel(2, 1)[c] = 0.25f - 0.02f; // all four off by 0.02: error 0.02
    const ui::DifferencePane d = ui::differencePane(a, b);
    const ImageError metric = compareImages(a, b);
    EXPECT_DOUBLE_EQ(d.rmse, metric.rmse);
    EXPECT_DOUBLE_EQ(d.psnrDb, metric.psnrDb);
    EXPECT_NEAR(d.maxError, 0.04, 1e-6);
    EXPECT_DOUBLE_EQ(d.scaleMax, 0.05);
    ASSERT_EQ(d.rgba.size(), size_t(3 * 2 * 4));
    const auto at = [&](int x, int y) { return &d.rgba[size_t(y * 3 + x) * 4]; };
    const auto expect = [&](int x, int y, double t) {
        const auto c = ui::differenceColour(t);
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(at(x, y)[k], c[size_t(k)]) << x << "," << y;
        EXPECT_EQ(at(x, y)[3], 255);
    };
    expect(0, 0, 0.0);
    expect(1, 0, 0.04 / 0.05);
    expect(2, 1, 0.02 / 0.05);
    // The mean square of the pixels' errors is the square of the image's RMSE.
    EXPECT_NEAR((0.04 * 0.04 + 0.02 * 0.02) / 6.0, metric.rmse * metric.rmse, 1e-9);
    EXPECT_THROW(ui::differencePane(a, Image(2, 2)), renderer::RenderError);
}

// The render thread draws a split request's two panes with their own settings, in one view: each pane's
// pixels are what the same renderer draws for that pane's settings alone, and |A - B|'s RMSE is the
// metric of those two float images.
TEST(SplitView, TheRenderThreadDrawsEachPaneWithItsSettingsAndTheDifferenceOfThoseImages) {
    std::unique_ptr<RenderThread> thread;
    try {
        thread = std::make_unique<RenderThread>();
    } catch (const std::exception& e) {
        if (const char* r = std::getenv("REQUIRE_GL"); r && std::string(r) == "1") FAIL() << e.what();
        GTEST_SKIP() << "no headless GL context: " << e.what();
    }
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(24), builtinPreset("grey-ramp"));
    thread->setScenes(std::make_shared<const SplatScene>(scene), {});
    ViewRequest request;
    // Far enough that the kernels are minified: low-pass and reconstruction differ visibly.
    request.plane = makeImagePlane(Camera{.azimuthDeg = 30, .elevationDeg = 20, .distance = 6.0},
                                   scene.centre, scene.radius, 120, 96);
    request.levels = ViewRequest::Levels::FullOnly;
    SplatSettings view;
    view.density = 4.0;
    // Back to front: no early termination, whose refreshes may stop at another slice from run to run.
    request.full = ui::paneSettings(view, {FilterMode::Reconstruction, Compositing::SheetBackToFront});
    request.second = ViewRequest::SecondPane{
        ui::paneSettings(view, {FilterMode::LowPass, Compositing::SheetBackToFront}), {}};
    request.difference = true;
    const uint64_t id = thread->requestView(request);
    thread->waitForView(id);
    ASSERT_FALSE(thread->takeError());
    const std::optional<RenderedView> shown = thread->takeView();
    ASSERT_TRUE(shown && shown->difference);
    ASSERT_EQ(shown->rgba.size(), size_t(120 * 96 * 4));
    ASSERT_EQ(shown->secondRgba.size(), shown->rgba.size());

    // Each pane alone, as the viewport would show it and as floats.
    struct Alone {
        std::vector<uint8_t> shown;
        Image image;
    };
    const auto alone = [&](const SplatSettings& settings) {
        return thread
            ->run([&, settings](Renderers& r) {
                r.full->render(request.plane, settings);
                Alone out{std::vector<uint8_t>(120 * 96 * 4), r.full->readback()};
                glGetTextureImage(r.full->displayTexture(request.background.data()), 0, GL_RGBA,
                                  GL_UNSIGNED_BYTE, GLsizei(out.shown.size()), out.shown.data());
                return out;
            })
            .get();
    };
    const Alone a = alone(request.full), b = alone(request.second->full);
    const auto largest = [](const std::vector<uint8_t>& x, const std::vector<uint8_t>& y) {
        int worst = 0;
        for (size_t i = 0; i < x.size(); ++i)
            worst = std::max(worst, std::abs(int(x[i]) - int(y[i])));
        return worst;
    };
    EXPECT_LE(largest(shown->rgba, a.shown), 1) << "the left pane is not its settings' image";
    EXPECT_LE(largest(shown->secondRgba, b.shown), 1) << "the right pane is not its settings' image";
    EXPECT_GT(largest(a.shown, b.shown), 20) << "the two filters should differ in this view";
    const ImageError metric = compareImages(a.image, b.image);
    EXPECT_GT(metric.rmse, 1e-3);
    EXPECT_NEAR(shown->difference->rmse, metric.rmse, 1e-6 * std::max(1.0, metric.rmse));
    EXPECT_NEAR(shown->difference->psnrDb, metric.psnrDb, 1e-3);
    std::printf("[ split    ] reconstruction vs low-pass: RMSE %.6f, PSNR %.2f dB (scale top %.3g)\n",
                shown->difference->rmse, shown->difference->psnrDb, shown->difference->scaleMax);
}
