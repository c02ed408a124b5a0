// The parameters chosen by the kind of driver: llvmpipe's and a GPU's, each from its own measurements.
#include "renderer/gl/driver_profile.h"

#include "scoped_env.h"

#include <gtest/gtest.h>


using renderer::driverProfile;

namespace {

// SPLATLAB_DRIVER_PROFILE set to `kind` (nullptr: cleared) for one scope.
struct ForcedProfile : testing_support::ScopedEnv {
    explicit ForcedProfile(const char* kind) : ScopedEnv("SPLATLAB_DRIVER_PROFILE", kind) {}
};

} // namespace

TEST(DriverProfile, LlvmpipeCullsHiddenSplatsAndTakesNarrowRunsShortChunksAndAColumnAnInvocation) {
    const ForcedProfile none(nullptr);
    const auto p = driverProfile("llvmpipe (LLVM 15.0.6, 256 bits)");
    EXPECT_TRUE(p.software);
    EXPECT_TRUE(p.occlusionCulling);
    EXPECT_EQ(p.runLanes, 8);
    EXPECT_EQ(p.listChunkSlices, 16u);
    EXPECT_FALSE(p.compositePerPixel);
    EXPECT_FALSE(p.deferredListChecks) << "llvmpipe sizes each part's lists from a read-back";
}

TEST(DriverProfile, AGpuKeepsHiddenSplatsAndTakesFullWarpsAndLongChunks) {
    const ForcedProfile none(nullptr);
    for (const char* name :
         {"NVIDIA H200/PCIe/SSE2", "NVIDIA H100 80GB HBM3/PCIe/SSE2", "AMD Radeon RX 7900 XTX"}) {
        const auto p = driverProfile(name);
        EXPECT_FALSE(p.software) << name;
        EXPECT_FALSE(p.occlusionCulling) << name;
        EXPECT_EQ(p.runLanes, 64) << name;
        EXPECT_EQ(p.listChunkSlices, 64u) << name;
        EXPECT_FALSE(p.compositePerPixel) << name << ": the pixel layout awaits a GPU's measurement";
        EXPECT_TRUE(p.deferredListChecks) << name << ": a GPU reads nothing back inside a frame";
    }
    // A name that merely mentions llvmpipe later is not Mesa's software rasteriser.
    EXPECT_FALSE(driverProfile("NVIDIA (not llvmpipe)").software);
}

TEST(DriverProfile, TheEnvironmentForcesEitherProfileOnAnyDriver) {
    {
        ForcedProfile gpu("gpu");
        EXPECT_FALSE(driverProfile("llvmpipe (LLVM 15.0.6, 256 bits)").occlusionCulling);
    }
    {
        ForcedProfile soft("llvmpipe");
        EXPECT_TRUE(driverProfile("NVIDIA H200/PCIe/SSE2").occlusionCulling);
    }
}
