#include "renderer/gl/driver_profile.h"

#include <cstdlib>
#include <string>

namespace renderer {

DriverProfile driverProfile(std::string_view glRenderer) {
    bool software = glRenderer.substr(0, 8) == "llvmpipe";
    if (const char* forced = std::getenv("SPLATLAB_DRIVER_PROFILE"); forced && *forced)
        software = std::string(forced) == "llvmpipe";
    if (!software) return DriverProfile{};
    return DriverProfile{.software = true, .runLanes = 8, .listChunkSlices = 16, .occlusionCulling = true,
                         .deferredListChecks = false};
}

} // namespace renderer
