// GPU memory: a scene that does not fit must give a RenderError saying how much it needs and how much
// is free, never a driver crash. The limit stands in for a full GPU (llvmpipe reports no free memory).
#include "gl_fixture.h"
#include "renderer/errors.h"
#include "renderer/model/procedural.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/model/transfer_function.h"

#include <gtest/gtest.h>

using namespace renderer;

class GpuMemory : public GlTest {};

TEST_F(GpuMemory, SceneOverTheLimitIsRefusedWithSizesAndTheRendererStaysUsable) {
    // 128 x 128 x 64 voxels: 2 MiB of classes alone, over a 1 MiB limit.
    const SplatScene scene = buildSplatScene(makeCheckerboard({128, 128, 64}, 8), builtinPreset("grey-ramp"));
    SplatRenderer gl;
    gl.setMemoryLimit(uint64_t(1) << 20);
    try {
        gl.setScene(scene);
        FAIL() << "expected RenderError";
    } catch (const RenderError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("checkerboard: needs "), std::string::npos) << msg;
        EXPECT_NE(msg.find(" MiB of GPU memory, 1 MiB free"), std::string::npos) << msg;
    }
    // Nothing was allocated or left half-done: lifting the limit, the same renderer takes the scene.
    gl.setMemoryLimit(0);
    gl.setScene(scene);
    EXPECT_GT(gl.sceneBytes(), uint64_t(2) << 20);
    gl.setMemoryLimit(gl.sceneBytes()); // exactly what it holds: replacing it fits
    gl.setScene(scene);
}

TEST_F(GpuMemory, TheCheckBeforeUploadingCountsEveryBufferTheSceneTakes) {
    // The check must see what setScene then allocates, the command array and where slices start
    // included (it once counted two of four command arrays): a limit one byte short of it is refused
    // before anything is uploaded.
    const SplatScene scene = buildSplatScene(makeCheckerboard({48, 40, 32}, 4), builtinPreset("grey-ramp"));
    uint64_t bytes = 0;
    {
        SplatRenderer measured;
        measured.setScene(scene);
        bytes = measured.sceneBytes();
    }
    SplatRenderer gl;
    gl.setMemoryLimit(bytes - 1);
    EXPECT_THROW(gl.setScene(scene), RenderError);
    gl.setMemoryLimit(bytes);
    gl.setScene(scene);
    EXPECT_EQ(gl.sceneBytes(), bytes);
}

TEST_F(GpuMemory, AnotherVolumeStartsTheFramesWorkingBuffersAfresh) {
    // The frame passes' buffers grow to the largest frame drawn; a small volume after a large one holds
    // what the small one alone would, not the large one's.
    const SplatScene large = buildSplatScene(makeCheckerboard({96, 96, 96}, 8), builtinPreset("grey-ramp"));
    const SplatScene small = buildSplatScene(makeCheckerboard({16, 16, 16}, 4), builtinPreset("grey-ramp"));
    SplatSettings s;
    s.compositing = Compositing::SheetFrontToBack;
    const auto plane = [](const SplatScene& scene, int size) {
        return makeImagePlane(Camera{}, scene.centre, scene.radius, size, size);
    };
    SplatRenderer alone;
    alone.setScene(small);
    alone.render(plane(small, 64), s);
    SplatRenderer gl;
    gl.setScene(large);
    gl.render(plane(large, 256), s);
    const uint64_t afterLarge = gl.workingBytes();
    gl.setScene(small);
    gl.render(plane(small, 64), s);
    EXPECT_GT(afterLarge, 8 * alone.workingBytes());
    EXPECT_EQ(gl.workingBytes(), alone.workingBytes());
    // The same volume again (a TF or window edit) keeps them: no reallocation a frame.
    gl.render(plane(small, 64), s);
    const uint64_t kept = gl.workingBytes();
    gl.setScene(small);
    gl.render(plane(small, 64), s);
    EXPECT_EQ(gl.workingBytes(), kept);
}
