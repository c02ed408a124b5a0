// The Performance panel: PerfHistory joins each render to its GPU times (which arrive renders later)
// and summarises them; the panel's controls set the load and clear the history.
#include "imgui_null.h"
#include "ui/panels.h"
#include "ui/perf_history.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

using ::testing::HasSubstr;
using ::testing::Not;

namespace {

renderer::FrameStats rendered(uint64_t frame, double cpuMs, uint64_t splats) {
    renderer::FrameStats f;
    f.frame = frame;
    f.cpuMs = cpuMs;
    f.splatsDrawn = splats;
    f.frameUploadBytes = 100 * frame;
    f.firstUsePrograms = int(frame % 2);
    return f;
}

renderer::FrameStats timed(uint64_t gpuFrame, double gpuMs) {
    renderer::FrameStats f;
    f.gpuFrame = gpuFrame;
    f.gpuMs = gpuMs;
    f.passMs[size_t(renderer::GpuPass::Splats)] = 0.75 * gpuMs;
    f.passMs[size_t(renderer::GpuPass::Composite)] = 0.25 * gpuMs;
    return f;
}

} // namespace

TEST(PerfHistory, TimesJoinTheRenderTheyAreOfOnceAndOlderUntimedRendersLeave) {
    ui::PerfHistory h;
    for (uint64_t k = 1; k <= 5; ++k) h.addRender(rendered(k, 2.0 * double(k), 1000 * k), k > 1 ? 30.0 : 0.0);
    EXPECT_TRUE(h.samples().empty());   // no times yet
    h.addTimes(timed(3, 12.0));         // render 3's times; 1 and 2 will never get theirs
    h.addTimes(timed(3, 12.0));         // read again: no second sample
    ASSERT_EQ(h.samples().size(), 1u);
    const ui::PerfSample& s = h.samples().front();
    EXPECT_EQ(s.frame, 3u);
    EXPECT_DOUBLE_EQ(s.cpuMs, 6.0);
    EXPECT_DOUBLE_EQ(s.gpuMs, 12.0);
    EXPECT_DOUBLE_EQ(s.intervalMs, 30.0);
    EXPECT_EQ(s.splats, 3000u);
    EXPECT_EQ(s.uploadBytes, 300u);
    EXPECT_EQ(s.firstUsePrograms, 1);   // the hover says its times include compiles
    EXPECT_DOUBLE_EQ(s.passMs[size_t(renderer::GpuPass::Splats)], 9.0);
    h.addTimes(timed(2, 5.0));   // older than what was taken: ignored
    h.addTimes(timed(5, 20.0));
    ASSERT_EQ(h.samples().size(), 2u);
    EXPECT_EQ(h.samples().back().frame, 5u);
    h.clear();
    EXPECT_TRUE(h.samples().empty());
    EXPECT_EQ(h.summary().renders, 0u);
}

TEST(PerfHistory, KeepsTheNewestRendersAndRendersWaitingTooLongLeave) {
    ui::PerfHistory h;
    const uint64_t renders = ui::PerfHistory::kCapacity + 60;
    for (uint64_t k = 1; k <= renders; ++k) {
        h.addRender(rendered(k, 1.0, 10), 0.0);
        h.addTimes(timed(k, 4.0));
    }
    ASSERT_EQ(h.samples().size(), ui::PerfHistory::kCapacity);
    EXPECT_EQ(h.samples().front().frame, renders - ui::PerfHistory::kCapacity + 1);
    EXPECT_EQ(h.samples().back().frame, renders);
    // A render whose times never come (the timer ring was full) leaves after kPending more renders.
    ui::PerfHistory w;
    for (uint64_t k = 1; k <= ui::PerfHistory::kPending + 1; ++k) w.addRender(rendered(k, 1.0, 10), 0.0);
    w.addTimes(timed(1, 4.0));
    EXPECT_TRUE(w.samples().empty());
    w.addTimes(timed(2, 4.0));
    EXPECT_EQ(w.samples().size(), 1u);
}

TEST(PerfHistory, SummaryGivesMediansNearestRankP95AndRates) {
    ui::PerfHistory h;
    // GPU 1..20 ms in shuffled order, CPU half of it, splats 1000 a ms of GPU time; every other render
    // followed another (interval 50 ms), the rest came after a pause (no interval).
    const int order[20] = {7, 3, 19, 1, 12, 20, 5, 16, 9, 2, 14, 11, 18, 4, 8, 15, 6, 13, 10, 17};
    for (int k = 0; k < 20; ++k) {
        const double gpu = order[k];
        h.addRender(rendered(uint64_t(k + 1), gpu / 2.0, uint64_t(1000 * order[k])), k % 2 ? 50.0 : 0.0);
        h.addTimes(timed(uint64_t(k + 1), gpu));
    }
    const ui::PerfSummary s = h.summary();
    EXPECT_EQ(s.renders, 20u);
    EXPECT_DOUBLE_EQ(s.gpuMedianMs, 10.5);
    EXPECT_DOUBLE_EQ(s.gpuP95Ms, 19.0);   // the 19th of 20 (ceil(0.95 x 20))
    EXPECT_DOUBLE_EQ(s.gpuMinMs, 1.0);
    EXPECT_DOUBLE_EQ(s.gpuMaxMs, 20.0);
    EXPECT_DOUBLE_EQ(s.cpuMedianMs, 5.25);
    EXPECT_EQ(s.intervals, 10u);
    EXPECT_DOUBLE_EQ(s.intervalMedianMs, 50.0);
    EXPECT_NEAR(s.splatsPerSecond, 10500.0 / 10.5e-3, 1e-6);
    EXPECT_DOUBLE_EQ(s.passMedianMs[size_t(renderer::GpuPass::Splats)], 0.75 * 10.5);
    EXPECT_DOUBLE_EQ(s.passMedianMs[size_t(renderer::GpuPass::Resolve)], 0.0);
}

TEST(PerfHistory, SummaryTextGivesTheContextAndTheFiguresForAReport) {
    ui::PerfSummary s;
    s.renders = 58;
    s.gpuMedianMs = 74.2, s.gpuP95Ms = 91.8, s.gpuMinMs = 61.4, s.gpuMaxMs = 154.7, s.cpuMedianMs = 74.7;
    s.intervals = 57, s.intervalMedianMs = 95.2;
    s.splatsPerSecond = 4.16e5;
    s.passMedianMs[size_t(renderer::GpuPass::Splats)] = 9.1;
    s.passMedianMs[size_t(renderer::GpuPass::Composite)] = 40.4;
    EXPECT_EQ(ui::summaryText(s, "headsq 64x64x93, 955x545 px"),
              "SplatLab performance: headsq 64x64x93, 955x545 px\n"
              "58 renders: GPU median 74.20 ms (13.5 /s), p95 91.80, min 61.40, max 154.70 ms; CPU median 74.70 ms\n"
              "renders seen 10.5 /s; splats sent 4.16e+05 /s\n"
              "passes (medians): splats 9.10 ms, composite 40.40 ms\n");
    s.intervals = 0;
    EXPECT_THAT(ui::summaryText(s, ""), HasSubstr("renders seen: none back to back"));
}

TEST(PerfHistory, RenderContextNamesWhatChangesTheWork) {
    renderer::SplatSettings s;
    s.compositing = renderer::Compositing::SheetFrontToBack;
    renderer::FrameStats f;
    f.tiles = true;
    const auto context = [&] { return ui::renderContext("bonsai", {256, 256, 256}, {512, 512}, s, f, "llvmpipe"); };
    EXPECT_EQ(context(), "bonsai 256x256x256, 512x512 px, ewa, sheet-front-to-back (tiles), llvmpipe");
    s.occlusionCulling = false;
    EXPECT_EQ(context(), "bonsai 256x256x256, 512x512 px, ewa, sheet-front-to-back (tiles), no occlusion culling, llvmpipe");
    s.opaqueAlpha = 1.0;   // no early termination: nothing to cull against either
    EXPECT_EQ(context(), "bonsai 256x256x256, 512x512 px, ewa, sheet-front-to-back (tiles), no early termination, llvmpipe");
    s.opaqueAlpha = 0.998;
    s.compositing = renderer::Compositing::SheetBackToFront;   // culling acts front to back only
    EXPECT_THAT(context(), Not(HasSubstr("culling")));
    s.compositing = renderer::Compositing::SplatEverySample;
    EXPECT_THAT(context(), HasSubstr("no occlusion culling"));
    s.shading = renderer::SplatSettings::Shading::PerSplat;
    s.surfaceFlatten = 8.0;
    EXPECT_THAT(context(), HasSubstr(", shaded per-splat, surface splats, no occlusion culling, llvmpipe"));
}

TEST_F(ImGuiNull, PerformancePanelCopiesItsFiguresWithTheirContext) {
    ui::EditorState state;
    ui::PerfHistory history;
    auto body = [&] { ui::drawPerformancePanel(state, history, [] { return std::string("bonsai on llvmpipe"); }); };
    // Right of Clear, on the checkbox's row: found from the summary column's right edge (23 font sizes;
    // the chart column's Pause would stop the recording).
    const auto clickCopy = [&] {
        for (float y = 20.0f; y < 60.0f; y += 3.0f)
            for (float x = 290.0f; x > 150.0f; x -= 6.0f) {
                ImGui::SetClipboardText("");
                click(x, y, body);
                if (std::string(ImGui::GetClipboardText()).size() > 0) return true;
            }
        return false;
    };
    EXPECT_FALSE(clickCopy()) << "Copy must wait for a timed render";
    for (uint64_t k = 1; k <= 4; ++k) {
        history.addRender(rendered(k, 3.0, 100), 16.0);
        history.addTimes(timed(k, 8.0));
    }
    ASSERT_TRUE(clickCopy()) << "no Copy button";
    EXPECT_EQ(std::string(ImGui::GetClipboardText()), ui::summaryText(history.summary(), "bonsai on llvmpipe"));
    EXPECT_EQ(history.samples().size(), 4u);   // Clear was not hit on the way
}

TEST_F(ImGuiNull, PerformancePanelTurnsContinuousRenderingOnSpinsOnlyThenAndClears) {
    ui::EditorState state;
    ui::PerfHistory history;
    for (uint64_t k = 1; k <= 10; ++k) {
        history.addRender(rendered(k, 3.0, 100), 16.0);
        history.addTimes(timed(k, 8.0));
    }
    auto body = [&] { ui::drawPerformancePanel(state, history); };
    frame(body);
    // The checkbox: click along the summary column's first rows until it answers.
    for (float y = 20.0f; y < 60.0f && !state.perf.renderContinuously; y += 3.0f)
        for (float x = 10.0f; x < 60.0f && !state.perf.renderContinuously; x += 10.0f) click(x, y, body);
    ASSERT_TRUE(state.perf.renderContinuously) << "no Render continuously checkbox";
    EXPECT_EQ(history.samples().size(), 10u);
    // The spin slider, below it: a drag that ends near its left end sets a speed (a plain click types).
    auto dragToLeftEnd = [&](float y) {
        mouse(20.0f, y, true);
        frame(body);
        mouse(40.0f, y, true);
        frame(body);
        mouse(20.0f, y, true);
        frame(body);
        mouse(20.0f, y, false);
        frame(body);
    };
    float spinY = -1.0f;
    for (float y = 30.0f; y < 90.0f && spinY < 0.0f; y += 3.0f) {
        dragToLeftEnd(y);
        if (state.perf.spinDegPerS != 0.0) spinY = y;
    }
    ASSERT_GT(spinY, 0.0f) << "no Spin slider";
    EXPECT_LT(state.perf.spinDegPerS, 0.0);   // its left end turns the other way
    EXPECT_GE(state.perf.spinDegPerS, -90.0);
    // Not rendering continuously, the slider takes no clicks.
    state.perf = {};
    dragToLeftEnd(spinY);
    EXPECT_EQ(state.perf.spinDegPerS, 0.0);
    // Clear, beside the checkbox.
    for (float y = 20.0f; y < 60.0f && !history.samples().empty(); y += 3.0f)
        for (float x = 140.0f; x < 300.0f && !history.samples().empty(); x += 8.0f) click(x, y, body);
    EXPECT_TRUE(history.samples().empty()) << "no Clear button";
}
