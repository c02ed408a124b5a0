// The split view (ui/split_view.h): its pane layout, each pane's settings, the difference pane's figures
// against the project's metric, and the render thread drawing both panes of a request with their own
// settings and |A - B| of exactly those two images.
#include "render_thread.h"
#include "split_truth.h"
#include "ui/split_view.h"

#include "renderer/errors.h"
#include "renderer/math/metrics.h"
#include "renderer/model/procedural.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "renderer/oracle/ground_truth.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <thread>

using namespace renderer;

TEST(SplitView, PanesAreEqualSideBySideAndFitTheViewport) {
    const std::vector<ui::PaneRect> three = ui::splitPaneRects(955, 545, 2, true);
    ASSERT_EQ(three.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(three[i].x, int(i) * 318);
        EXPECT_EQ(three[i].y, 0);
        EXPECT_EQ(three[i].width, 318) << "every pane the same size: they share one image plane";
        EXPECT_EQ(three[i].height, 545);
    }
    EXPECT_LE(three.back().x + three.back().width, 955);
    const std::vector<ui::PaneRect> two = ui::splitPaneRects(955, 545, 2, false);
    ASSERT_EQ(two.size(), 2u);
    EXPECT_EQ(two[1].x, 477);
    EXPECT_EQ(two[1].width, 477);
    EXPECT_EQ(ui::splitPaneRects(1, 0, 2, false)[1].width, 1) << "a pane is never empty";
    EXPECT_EQ((ui::SplitView{.enabled = true, .difference = ui::SplitDifference::AgainstB}).paneCount(), 3);
    EXPECT_EQ(
        (ui::SplitView{.enabled = true, .imagePanes = 4, .difference = ui::SplitDifference::AgainstTruth})
            .paneCount(),
        5);
    EXPECT_EQ((ui::SplitView{.enabled = false, .difference = ui::SplitDifference::AgainstB}).paneCount(), 1);
}

TEST(SplitView, FourPanesAreAGridAndTheDifferenceAColumnBesideIt) {
    const ui::SplitLayout grid = ui::splitLayout(955, 545, 4, false);
    ASSERT_EQ(grid.panes.size(), 4u);
    EXPECT_FALSE(grid.difference);
    const int w = 477, h = 272;
    const int expected[4][2] = {{0, 0}, {w, 0}, {0, h}, {w, h}}; // A B over C D
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(grid.panes[i].x, expected[i][0]) << "pane " << i;
        EXPECT_EQ(grid.panes[i].y, expected[i][1]) << "pane " << i;
        EXPECT_EQ(grid.panes[i].width, w);
        EXPECT_EQ(grid.panes[i].height, h);
    }
    const ui::SplitLayout withDifference = ui::splitLayout(955, 545, 4, true);
    ASSERT_TRUE(withDifference.difference);
    EXPECT_EQ(withDifference.panes[3].x, 318) << "the grid narrows to two of three columns";
    EXPECT_EQ(withDifference.difference->x, 636);
    EXPECT_EQ(withDifference.difference->y, 136) << "centred beside the grid";
    EXPECT_EQ(withDifference.difference->width, withDifference.panes[0].width);
    EXPECT_EQ(withDifference.difference->height, withDifference.panes[0].height);
    EXPECT_LE(withDifference.difference->y + withDifference.difference->height, 545);
    EXPECT_EQ(ui::splitDifferenceFromName("truth"), ui::SplitDifference::AgainstTruth);
    EXPECT_THROW(ui::splitDifferenceFromName("c"), renderer::RenderError);
}

TEST(SplitView, AnUpsampledImageKeepsAConstantAndInterpolatesBetweenPixelCentres) {
    Image small(2, 1);
    for (int c = 0; c < 4; ++c)
        small.pixel(0, 0)[c] = 0.0f, small.pixel(1, 0)[c] = 1.0f;
    const Image big = ui::upsampleBilinear(small, 8, 4);
    ASSERT_EQ(big.width, 8);
    ASSERT_EQ(big.height, 4);
    EXPECT_FLOAT_EQ(big.pixel(0, 0)[0], 0.0f) << "edges clamped";
    EXPECT_FLOAT_EQ(big.pixel(7, 3)[0], 1.0f);
    EXPECT_FLOAT_EQ(big.pixel(4, 2)[0], 0.5f + 0.125f); // x = 4.5 / 4 - 0.5 = 0.625 of the way
    for (int x = 1; x < 8; ++x)
        EXPECT_GE(big.pixel(x, 1)[2], big.pixel(x - 1, 1)[2]);
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

// The render thread draws a split request's four panes with their own settings, in one view: each pane's
// pixels are what the same renderer draws for that pane's settings alone, |A - B|'s RMSE is the metric of
// A's and B's float images, and the first pane's float image comes back when asked (|A - truth|).
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
    for (const ui::SplitPane pane : {ui::SplitPane{FilterMode::LowPass, Compositing::SheetBackToFront},
                                     ui::SplitPane{FilterMode::Ewa, Compositing::XRay},
                                     ui::SplitPane{FilterMode::Adaptive, Compositing::SheetBackToFront}})
        request.others.push_back({ui::paneSettings(view, pane), {}});
    request.difference = true;
    request.keepFirstPane = true;
    const uint64_t id = thread->requestView(request);
    thread->waitForView(id);
    ASSERT_FALSE(thread->takeError());
    const std::optional<RenderedView> shown = thread->takeView();
    ASSERT_TRUE(shown && shown->difference && shown->firstPane);
    ASSERT_EQ(shown->rgba.size(), size_t(120 * 96 * 4));
    ASSERT_EQ(shown->otherRgba.size(), 3u);

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
    const Alone a = alone(request.full);
    const auto largest = [](const std::vector<uint8_t>& x, const std::vector<uint8_t>& y) {
        int worst = 0;
        for (size_t i = 0; i < x.size(); ++i)
            worst = std::max(worst, std::abs(int(x[i]) - int(y[i])));
        return worst;
    };
    EXPECT_LE(largest(shown->rgba, a.shown), 1) << "pane A is not its settings' image";
    std::vector<Alone> others;
    for (size_t i = 0; i < 3; ++i) {
        others.push_back(alone(request.others[i].full));
        ASSERT_EQ(shown->otherRgba[i].size(), shown->rgba.size());
        EXPECT_LE(largest(shown->otherRgba[i], others[i].shown), 1)
            << "pane "
            << "BCD"[i] << " is not its settings' image";
        EXPECT_GT(largest(a.shown, others[i].shown), 20) << "pane "
                                                         << "BCD"[i] << " should differ from A in this view";
    }
    EXPECT_LT(compareImages(*shown->firstPane, a.image).rmse, 1e-6) << "the first pane's float image";
    const ImageError metric = compareImages(a.image, others[0].image);
    EXPECT_GT(metric.rmse, 1e-3);
    EXPECT_NEAR(shown->difference->rmse, metric.rmse, 1e-6 * std::max(1.0, metric.rmse));
    EXPECT_NEAR(shown->difference->psnrDb, metric.psnrDb, 1e-3);
    std::printf("[ split    ] reconstruction vs low-pass: RMSE %.6f, PSNR %.2f dB (scale top %.3g)\n",
                shown->difference->rmse, shown->difference->psnrDb, shown->difference->scaleMax);
}

namespace {

// A small scene's truths: a few thousand rays each.
struct TruthScene {
    std::shared_ptr<const SplatScene> scene = std::make_shared<const SplatScene>(
        buildSplatScene(makeMarschnerLobb(16), builtinPreset("grey-ramp")));
    ImagePlane plane(double azimuth, int width = 24, int height = 16) const {
        return makeImagePlane(Camera{.azimuthDeg = azimuth, .elevationDeg = 20, .distance = 3.0},
                              scene->centre, scene->radius, width, height);
    }
};

} // namespace

// The split view's truth is the ground truth of the view it was asked for: renderGroundTruth of that
// view, at the pane's size, once done; its key holds what the truth depends on.
TEST(SplitTruth, CoarseThenFullAreTheGroundTruthOfTheViewAsked) {
    const TruthScene t;
    SplatSettings settings;
    settings.density = 4.0;
    const ImagePlane plane = t.plane(30);
    SplitTruth truth({}, {}, false); // at normal priority: other load on the machine must not starve the test
    const std::string key = SplitTruth::viewKey(plane, settings, 1);
    truth.want(key, plane, settings, [&] { return t.scene; });
    EXPECT_TRUE(truth.computing());
    truth.waitUntilDone();
    EXPECT_FALSE(truth.computing());
    ASSERT_FALSE(truth.error()) << *truth.error();
    const std::optional<SplitTruth::Truth> full = truth.latest();
    ASSERT_TRUE(full);
    EXPECT_EQ(full->key, key);
    EXPECT_FALSE(full->coarse);
    EXPECT_EQ(full->computedWidth, 24);
    const Image direct = renderGroundTruth(*t.scene, plane, settings);
    EXPECT_EQ(compareImages(*full->image, direct).rmse, 0.0);
    EXPECT_GT(compareImages(direct, Image(24, 16)).rmse, 0.02) << "the view shows something";
    EXPECT_NE(SplitTruth::viewKey(plane, settings, 2), key) << "another scene, another truth";
    settings.filter = FilterMode::LowPass;
    EXPECT_EQ(SplitTruth::viewKey(plane, settings, 1), key) << "the truth does not depend on the filter";
}

// A camera move while the truth computes supersedes it: from the moment the new view is wanted, the old
// view's truth is never handed out, whether it was finished or not, and the new view's truth follows.
TEST(SplitTruth, ANewViewWhileTheTruthComputesSupersedesItAndNoStaleTruthIsShown) {
    const TruthScene t;
    SplatSettings settings;
    settings.density = 4.0;
    SplitTruth truth({}, {}, false); // at normal priority: other load on the machine must not starve the test
    const ImagePlane first = t.plane(30, 96, 64), moved = t.plane(75);
    const std::string firstKey = SplitTruth::viewKey(first, settings, 1),
                      movedKey = SplitTruth::viewKey(moved, settings, 1);
    truth.want(firstKey, first, settings, [&] { return t.scene; });
    std::this_thread::sleep_for(std::chrono::milliseconds(20)); // under way (96 x 64 takes seconds)
    EXPECT_TRUE(truth.computing());
    truth.want(movedKey, moved, settings, [&] { return t.scene; });
    for (int i = 0; i < 2000 && truth.computing(); ++i) {
        truth.want(movedKey, moved, settings, [&] { return t.scene; }); // as the editor asks each frame
        if (const auto shown = truth.latest()) {
            EXPECT_EQ(shown->key, movedKey) << "a stale truth was shown";
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    truth.waitUntilDone();
    ASSERT_FALSE(truth.error()) << *truth.error();
    const std::optional<SplitTruth::Truth> shown = truth.latest();
    ASSERT_TRUE(shown);
    EXPECT_EQ(shown->key, movedKey);
    EXPECT_FALSE(shown->coarse);
    EXPECT_EQ(compareImages(*shown->image, renderGroundTruth(*t.scene, moved, settings)).rmse, 0.0);
    // Turned off: nothing is handed out.
    truth.clear();
    EXPECT_FALSE(truth.latest());
    EXPECT_FALSE(truth.computing());
}
