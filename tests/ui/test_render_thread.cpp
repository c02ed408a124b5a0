// The editor's render thread (app/render_thread.h) on its own: a newer view request supersedes the one in
// flight, and a progressive request gives each level, coarsest first, then the full frame, with each
// level's error against it. SPLATLAB_RENDER_DELAY_MS makes every frame slow, as a large scan's are.
#include "render_thread.h"
#include "scoped_env.h"

#include "renderer/model/procedural.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "renderer/model/volume.h"
#include "renderer/oracle/image_slabs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

using namespace renderer;

namespace {

double msSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

ViewRequest request(const SplatScene& scene, double azimuth, ViewRequest::Levels levels) {
    ViewRequest r;
    r.plane = makeImagePlane(Camera{.azimuthDeg = azimuth, .elevationDeg = 20}, scene.centre, scene.radius, 96, 80);
    r.levels = levels;
    return r;
}

// A smooth blob 48 voxels across and its levels at 1/2 and 1/4 (one fine voxel each), set on `thread`;
// a progressive request for it at 96x80.
ViewRequest blobWithLevels(RenderThread& thread) {
    Volume v;
    v.name = "blob";
    v.dims = {48, 48, 48};
    for (int z = 0; z < 48; ++z)
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 48; ++x) {
                const glm::dvec3 d = glm::dvec3(x, y, z) - 23.5;
                v.values.floats().push_back(float(std::exp(-glm::dot(d, d) / (2.0 * 9.0 * 9.0))));
            }
    updateRange(v);
    const TransferFunction ramp = builtinPreset("grey-ramp");
    const SplatScene full = buildSplatScene(v, ramp, v.range);
    std::vector<Volume> levels{halfResolution(v, Downsample::PickOne)};
    levels.push_back(halfResolution(levels.back(), Downsample::PickOne));
    RenderThread::Scenes scenes;
    ViewRequest r = request(full, 30, ViewRequest::Levels::Progressive);
    r.full.density = 0.2;
    for (const Volume& level : levels) {
        scenes.push_back(std::make_shared<const SplatScene>(buildSplatScene(level, ramp, v.range)));
        r.coarse.push_back(r.full);
        r.coarse.back().density = densityFor(level, v, r.full.density);
    }
    thread.setScenes(std::make_shared<const SplatScene>(full), scenes);
    return r;
}

// Images of a request as they come, until its last (at most 30 s).
std::vector<RenderedView> imagesUntilLast(RenderThread& thread, uint64_t id) {
    std::vector<RenderedView> shown;
    // Images replace each other in one slot: poll fast enough to see each (the test's frames take ms).
    const auto start = std::chrono::steady_clock::now();
    for (bool done = false; !done && msSince(start) < 30000.0;) {
        if (auto view = thread.takeView()) {
            done = view->last;
            shown.push_back(std::move(*view));
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    thread.waitForView(id);
    return shown;
}

} // namespace

// Each test's render thread, which needs a GL context of its own: without EGL the test skips
// (REQUIRE_GL=1: fails).
class RenderThreadTest : public ::testing::Test {
protected:
    void SetUp() override {
        try {
            thread = std::make_unique<RenderThread>();
        } catch (const std::exception& e) {
            if (const char* r = std::getenv("REQUIRE_GL"); r && std::string(r) == "1") FAIL() << e.what();
            GTEST_SKIP() << "no headless GL context: " << e.what();
        }
    }
    std::unique_ptr<RenderThread> thread;
};

// Its frames each wait a second first (SPLATLAB_RENDER_DELAY_MS), as a large scan's take long.
class SlowRenderThread : public RenderThreadTest {
protected:
    void SetUp() override {
        const testing_support::ScopedEnv slow("SPLATLAB_RENDER_DELAY_MS", "1000");
        RenderThreadTest::SetUp();
    }
};

// Request A, then B while A waits out its slow frame: A stops once it missed the budget and never shows;
// B's image is the only one.
TEST_F(SlowRenderThread, ANewerRequestSupersedesTheFrameInFlight) {
    std::atomic<int> images{0};
    thread->setOnImage([&] { ++images; });
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(16), builtinPreset("grey-ramp"));
    thread->setScenes(std::make_shared<const SplatScene>(scene), {});
    const auto start = std::chrono::steady_clock::now();
    thread->requestView(request(scene, 0, ViewRequest::Levels::FullOnly));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const uint64_t b = thread->requestView(request(scene, 90, ViewRequest::Levels::FullOnly));
    thread->waitForView(b);
    const double ms = msSince(start);
    const std::optional<RenderedView> shown = thread->takeView();
    ASSERT_TRUE(shown);
    EXPECT_EQ(shown->request, b);
    // Not superseded, A's frame would have shown (and taken its full second before B's began).
    EXPECT_EQ(images.load(), 1) << "the superseded request showed an image";
    std::printf("[ render   ] A then B: B's image %.0f ms after A was asked (1 s frames)\n", ms);
    EXPECT_FALSE(thread->takeError()) << "a superseded frame is not an error";
}

// A progressive request with a budget nothing fits: the coarsest level first, then each finer one and the
// full frame last, every level within a stated RMSE of the full frame on a smooth blob.
TEST_F(RenderThreadTest, AProgressiveRequestGivesEachLevelThenTheFullFrame) {
    ViewRequest r = blobWithLevels(*thread);
    r.budgetMs = 1e-3;
    const std::vector<RenderedView> views = imagesUntilLast(*thread, thread->requestView(r));
    std::vector<int> shown;
    for (const RenderedView& view : views) shown.push_back(view.level);
    const std::optional<RenderedView> last = views.empty() ? std::nullopt : std::optional(views.back());
    ASSERT_TRUE(last) << (thread->takeError() ? "the render thread failed" : "no image in 30 s");
    EXPECT_EQ(shown.back(), 0) << "the full frame comes last";
    EXPECT_EQ(shown.front(), 2) << "the first image comes from the coarsest level";
    for (size_t i = 1; i < shown.size(); ++i) EXPECT_LT(shown[i], shown[i - 1]) << "levels come coarse to fine";
    std::printf("[ levels   ] RMSE against the full frame: 1/2 %.4f, 1/4 %.4f\n", last->levelRmse[1],
                last->levelRmse[2]);
    EXPECT_GE(last->levelRmse[2], 0.0);
    EXPECT_LT(last->levelRmse[2], 0.05);
    if (last->levelRmse[1] >= 0.0) {
        EXPECT_LT(last->levelRmse[1], 0.03);
    }
}

// A far view's request rests on its finest level (ViewRequest::finestLevel): progressive, the coarsest
// level, then finer ones down to it and no full frame; drawing one image, that level alone.
TEST_F(RenderThreadTest, AFarViewsRequestRestsOnItsLevelWithoutTheFullFrame) {
    ViewRequest r = blobWithLevels(*thread);
    r.budgetMs = 1e-3;
    r.finestLevel = 1;
    std::vector<RenderedView> views = imagesUntilLast(*thread, thread->requestView(r));
    ASSERT_FALSE(views.empty()) << (thread->takeError() ? "the render thread failed" : "no image in 30 s");
    EXPECT_EQ(views.front().level, 2);
    EXPECT_EQ(views.back().level, 1) << "the view rests on level 1";
    for (const RenderedView& view : views) {
        EXPECT_GE(view.level, 1) << "no full frame";
        EXPECT_EQ(view.finestLevel, 1);
    }
    r.levels = ViewRequest::Levels::FullOnly;   // one image a request (scripted runs)
    views = imagesUntilLast(*thread, thread->requestView(r));
    ASSERT_EQ(views.size(), 1u);
    EXPECT_EQ(views[0].level, 1);
    EXPECT_TRUE(views[0].last);
    r.finestLevel = 5;   // past the coarsest: the coarsest
    views = imagesUntilLast(*thread, thread->requestView(r));
    ASSERT_EQ(views.size(), 1u);
    EXPECT_EQ(views[0].level, 2);
}

// A still view that asks for slabs (ViewRequest::slabs): the full frame of sheets, then one more image,
// the same view in image-aligned slabs, equal to the CPU oracle's slabs to 8-bit rounding.
TEST_F(RenderThreadTest, AStillViewEndsInItsSlabFrameAfterTheSheets) {
    std::atomic<int> images{0};
    thread->setOnImage([&] { ++images; });
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(16), builtinPreset("grey-ramp"));
    thread->setScenes(std::make_shared<const SplatScene>(scene), {});
    ViewRequest r = request(scene, 30, ViewRequest::Levels::FullOnly);
    r.full.compositing = Compositing::SheetFrontToBack;
    r.background = {0.1f, 0.2f, 0.3f};
    thread->waitForView(thread->requestView(r));
    const std::optional<RenderedView> sheets = thread->takeView();
    ASSERT_TRUE(sheets && !sheets->slabs);
    r.slabs = SlabOptions{.thickness = 0.5, .postClassified = true};
    images = 0;
    thread->waitForView(thread->requestView(r));
    const std::optional<RenderedView> slabs = thread->takeView();
    ASSERT_TRUE(slabs) << (thread->takeError() ? "the render thread failed" : "no image");
    EXPECT_TRUE(slabs->slabs && slabs->last);
    EXPECT_EQ(images.load(), 2) << "the sheets' frame, then the slabs'";
    EXPECT_EQ(thread->slabNote(), "");
    const std::vector<uint8_t> oracle =
        displayPixels(renderImageAlignedSlabs(scene, r.plane, r.full, *r.slabs), r.background.data());
    ASSERT_EQ(slabs->rgba.size(), oracle.size());
    int fromOracle = 0, fromSheets = 0;
    for (size_t i = 0; i < oracle.size(); ++i) {
        fromOracle = std::max(fromOracle, std::abs(int(slabs->rgba[i]) - int(oracle[i])));
        fromSheets = std::max(fromSheets, std::abs(int(slabs->rgba[i]) - int(sheets->rgba[i])));
    }
    std::printf("[ slabs    ] largest difference from the oracle's slabs %d, from the sheets %d (of 255)\n",
                fromOracle, fromSheets);
    EXPECT_LE(fromOracle, 1);
    EXPECT_GE(fromSheets, 8) << "post-classified slabs are not the pre-classified sheets";
}

// Slabs the settings refuse (X-ray has no order to slice): the sheets' frame stays, the note says why,
// and it is no error of the render thread's.
TEST_F(RenderThreadTest, SlabsASettingRefusesLeaveTheSheetsAndSayWhy) {
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(16), builtinPreset("grey-ramp"));
    thread->setScenes(std::make_shared<const SplatScene>(scene), {});
    ViewRequest r = request(scene, 30, ViewRequest::Levels::FullOnly);
    r.full.compositing = Compositing::XRay;
    r.slabs = SlabOptions{};
    thread->waitForView(thread->requestView(r));
    const std::optional<RenderedView> shown = thread->takeView();
    ASSERT_TRUE(shown);
    EXPECT_FALSE(shown->slabs);
    EXPECT_NE(thread->slabNote().find("X-ray"), std::string::npos) << thread->slabNote();
    EXPECT_FALSE(thread->takeError());
}

// A newer view supersedes a slab frame in flight (in its set-up, or after a band of its dispatches): the
// slab frame never shows (drawn to the end, it would, before the newer view's). How soon the newer image
// comes is printed, not asserted: it is a time, and CI runs two tests at once.
TEST_F(RenderThreadTest, ANewerRequestSupersedesASlabFrameInFlight) {
    std::atomic<int> images{0};
    thread->setOnImage([&] { ++images; });
    const SplatScene scene = buildSplatScene(makeMarschnerLobb(32), builtinPreset("grey-ramp"));
    thread->setScenes(std::make_shared<const SplatScene>(scene), {});
    ViewRequest r = request(scene, 30, ViewRequest::Levels::FullOnly);
    r.plane = makeImagePlane(Camera{.azimuthDeg = 30, .elevationDeg = 20}, scene.centre, scene.radius, 160, 160);
    r.full.compositing = Compositing::SheetFrontToBack;
    r.slabs = SlabOptions{.thickness = 0.2, .postClassified = true};
    // How long the slab frame takes when nothing supersedes it.
    auto start = std::chrono::steady_clock::now();
    thread->waitForView(thread->requestView(r));
    const double wholeMs = msSince(start);
    ASSERT_TRUE(thread->takeView()->slabs);
    // Again, superseded once its sheets are shown.
    images = 0;
    thread->requestView(r);
    while (images.load() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    start = std::chrono::steady_clock::now();
    ViewRequest newer = r;
    newer.slabs.reset();
    const uint64_t b = thread->requestView(newer);
    thread->waitForView(b);
    const double newerMs = msSince(start);
    const std::optional<RenderedView> shown = thread->takeView();
    ASSERT_TRUE(shown);
    EXPECT_EQ(shown->request, b);
    EXPECT_EQ(images.load(), 2) << "the superseded slab frame showed";
    std::printf("[ slabs    ] whole request %.0f ms; a newer view's image %.0f ms after it was asked\n", wholeMs,
                newerMs);
}
