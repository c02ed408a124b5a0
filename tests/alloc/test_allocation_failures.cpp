// Running out of memory while rendering and in the editor's jobs: each failure names the volume, what was
// being allocated and its size, and what was shown before stays (the render thread keeps drawing the
// previous scene; a job leaves no half result). FailingAllocations makes one allocation fail on request.
#include "editor_jobs.h"
#include "failing_allocations.h"
#include "render_thread.h"

#include "renderer/errors.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/model/procedural.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "renderer/oracle/reference_renderer.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

using namespace renderer;
using ::testing::HasSubstr;

namespace {

constexpr size_t kKiB = 1024;

Volume lobb(int n, const char* name) {
    Volume v = makeMarschnerLobb(n);
    v.name = name;
    return v;
}

SplatScene classify(const Volume& v) { return buildSplatScene(v, builtinPreset("grey-ramp")); }

ViewRequest fullView(const SplatScene& scene, int width, int height) {
    ViewRequest r;
    r.plane = makeImagePlane(Camera{.azimuthDeg = 30, .elevationDeg = 20}, scene.centre, scene.radius, width,
                             height);
    r.levels = ViewRequest::Levels::FullOnly;
    return r;
}

// Without EGL these skip (REQUIRE_GL=1: fail), as the other GL suites do.
bool skipWithoutGl(const std::string& why) {
    if (const char* r = std::getenv("REQUIRE_GL"); r && std::string(r) == "1") ADD_FAILURE() << why;
    return true;
}

} // namespace

// The render thread cannot hold a view's pixels: the error names the volume, the pixels, their size and
// the view's; no image replaces the last one, and the next view (memory back) draws.
TEST(RenderThreadOutOfMemory, AViewWhosePixelsDoNotFitIsNamedAndTheNextViewDraws) {
    std::unique_ptr<RenderThread> thread;
    try {
        thread = std::make_unique<RenderThread>();
    } catch (const std::exception& e) {
        if (skipWithoutGl(e.what())) GTEST_SKIP() << "no headless GL context: " << e.what();
    }
    const SplatScene scene = classify(lobb(16, "small"));
    thread->setScenes(std::make_shared<const SplatScene>(scene), {});
    thread->waitForView(thread->requestView(fullView(scene, 96, 80)));
    ASSERT_TRUE(thread->takeView());
    {
        const FailingAllocations failing(256 * kKiB); // the view's RGBA8 pixels take 1 MiB
        thread->waitForView(thread->requestView(fullView(scene, 512, 512)));
    }
    const std::optional<std::string> error = thread->takeError();
    ASSERT_TRUE(error) << "a view that could not be read back must be reported";
    EXPECT_THAT(*error,
                HasSubstr("volume 'small': out of memory allocating the view's pixels (1.0 MiB) at 512x512"));
    EXPECT_FALSE(thread->takeView()) << "no (empty) image may replace the one on screen";

    thread->waitForView(thread->requestView(fullView(scene, 512, 512)));
    const std::optional<RenderedView> view = thread->takeView();
    ASSERT_TRUE(view) << "the render thread keeps running after the failure";
    EXPECT_EQ(view->width, 512);
    EXPECT_EQ(view->rgba.size(), size_t(512) * 512 * 4);
    EXPECT_FALSE(thread->takeError());
}

// A new volume whose lists cannot be copied for the GPU: the error names it and what was copied, and the
// view still shows the previous volume, pixel for pixel. The copies are of the runs, 16 bytes a
// run (the entries are the scene's own, shared), hence a threshold of 64 KiB.
TEST(RenderThreadOutOfMemory, AVolumeThatDoesNotFitIsNamedAndThePreviousOneStillDraws) {
    std::unique_ptr<RenderThread> thread;
    try {
        thread = std::make_unique<RenderThread>();
    } catch (const std::exception& e) {
        if (skipWithoutGl(e.what())) GTEST_SKIP() << "no headless GL context: " << e.what();
    }
    const SplatScene small = classify(lobb(16, "small"));
    const auto large = std::make_shared<const SplatScene>(classify(lobb(96, "large"))); // MiBs of lists
    thread->setScenes(std::make_shared<const SplatScene>(small), {});
    thread->waitForView(thread->requestView(fullView(small, 96, 80)));
    const std::optional<RenderedView> before = thread->takeView();
    ASSERT_TRUE(before);
    {
        const FailingAllocations failing(64 * kKiB);
        thread->setScenes(large, {});
        thread->waitForView(thread->requestView(fullView(small, 96, 80)));
    }
    const std::optional<std::string> error = thread->takeError();
    ASSERT_TRUE(error);
    EXPECT_THAT(
        *error,
        HasSubstr("volume 'large': out of memory allocating the copies of the slice lists for the GPU ("));
    const std::optional<RenderedView> after = thread->takeView();
    ASSERT_TRUE(after) << "the previous volume still draws";
    EXPECT_EQ(after->rgba, before->rgba) << "the view is the previous volume's";
}

// Opening a volume waits for its upload (setScenesNow): its failure reaches the caller, which then keeps
// its document.
TEST(RenderThreadOutOfMemory, SetScenesNowThrowsTheNamedErrorToTheCaller) {
    std::unique_ptr<RenderThread> thread;
    try {
        thread = std::make_unique<RenderThread>();
    } catch (const std::exception& e) {
        if (skipWithoutGl(e.what())) GTEST_SKIP() << "no headless GL context: " << e.what();
    }
    const auto large = std::make_shared<const SplatScene>(classify(lobb(96, "large")));
    const FailingAllocations failing(64 * kKiB);
    try {
        thread->setScenesNow(large, {});
        ADD_FAILURE() << "setScenesNow returned although the lists did not fit";
    } catch (const RenderError& e) {
        EXPECT_THAT(e.what(),
                    HasSubstr("volume 'large': out of memory allocating the copies of the slice lists"));
    }
    EXPECT_FALSE(thread->takeError()) << "reported once, to the caller";
}

// The renderer's read-back: the error names the volume, the image, its size and the frame's size; the
// image reads back once memory is there again.
TEST(SplatRendererOutOfMemory, AReadBackThatDoesNotFitIsNamed) {
    std::unique_ptr<HeadlessGl> gl;
    try {
        gl = HeadlessGl::create();
    } catch (const std::exception& e) {
        if (skipWithoutGl(e.what())) GTEST_SKIP() << "no headless GL context: " << e.what();
    }
    const SplatScene scene = classify(lobb(16, "small"));
    SplatRenderer splats;
    splats.setScene(scene);
    splats.render(fullView(scene, 256, 256).plane, SplatSettings{});
    {
        const FailingAllocations failing(512 * kKiB); // the image and its GL copy: 2 x 1 MiB of floats
        try {
            (void)splats.readback();
            ADD_FAILURE() << "readback returned although its image did not fit";
        } catch (const RenderError& e) {
            EXPECT_THAT(e.what(),
                        HasSubstr("volume 'small': out of memory allocating the read-back image (2.0 MiB) at "
                                  "256x256"));
        }
    }
    EXPECT_EQ(splats.readback().width, 256);
}

// The CPU reference (render --cpu, accuracy, the tests' oracle): the error names the volume and the view.
TEST(ReferenceRendererOutOfMemory, AnImageThatDoesNotFitIsNamed) {
    const SplatScene scene = classify(lobb(16, "small"));
    const FailingAllocations failing(512 * kKiB); // the 256x256 RGBA float image takes 1 MiB
    try {
        (void)renderReference(scene, fullView(scene, 256, 256).plane, SplatSettings{});
        ADD_FAILURE() << "renderReference returned although its image did not fit";
    } catch (const RenderError& e) {
        EXPECT_THAT(e.what(),
                    HasSubstr("volume 'small': out of memory allocating the CPU reference's splats and image at 256x256"));
    }
}

// The editor's gradient job: the field does not fit; the error names the volume and the gradients, and the
// job leaves no result (the editor keeps the volume unlit).
TEST(EditorJobsOutOfMemory, GradientsThatDoNotFitAreNamedAndLeaveNoResult) {
    const Volume volume = lobb(96, "large"); // 3 int16 a voxel: 5.1 MiB of gradients
    std::unique_ptr<GradientJob> job;
    {
        const FailingAllocations failing(1024 * kKiB);
        job = std::make_unique<GradientJob>(volume, std::vector<const Volume*>{});
        job->thread.join();
    }
    ASSERT_TRUE(job->done);
    EXPECT_FALSE(job->result);
    EXPECT_THAT(job->error, HasSubstr("volume 'large': out of memory allocating the gradients (5.1 MiB)"));
}
