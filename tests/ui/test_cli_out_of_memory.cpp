// The command line out of memory while rendering: one line naming the volume, what was being allocated,
// its size and the image's, and a failing exit (not a crash or a bare std::bad_alloc).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "shell_run.h"
#include "test_paths.h"

#include <array>
#include <cstdio>
#include <string>

using ::testing::HasSubstr;
using ::testing::Not;

namespace {

using testing_support::runShell;
using testing_support::ShellRun;

} // namespace

// 8192x8192 takes 4.5 GiB of render targets (four RGBA32F images, depth, display); the process may map
// 3 GiB (ulimit -v), so llvmpipe's allocation fails: GL_OUT_OF_MEMORY, which must come back named. The
// memory budget is set high so that its check (for the volume's voxels) does not refuse first.
TEST(CliOutOfMemory, RenderNamesTheVolumeAndTheBuffersThatDidNotFit) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: it cannot run under ulimit -v";
#endif
    const std::string headsq = (testing_support::assetDir() / "volumes" / "headsq.nhdr").string();
    const std::string out = (testing_support::testOutputDir() / "cli_out_of_memory.png").string();
    const ShellRun r = runShell(
        "ulimit -v 3145728 && env -u DISPLAY LIBGL_ALWAYS_SOFTWARE=1 SPLATLAB_MEMORY_BUDGET_MB=100000 "
        "\"" SPLATLAB_EXE "\" render \"" +
        headsq + "\" --out \"" + out + "\" --size 8192x8192 --frames 1 2>&1");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_THAT(
        r.output,
        HasSubstr("splatlab: volume 'headsq': out of GPU memory allocating the render targets (4.5 GiB) "
                  "at 8192x8192"));
    EXPECT_THAT(r.output, Not(HasSubstr("bad_alloc")));
}
