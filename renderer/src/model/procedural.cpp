// Analytic volumes (checkerboard, sphere shells, Marschner-Lobb): known signals for tests and the
// hard-case scenes. They are float32, unit spacing, origin 0; nothing here reads files.
#include "renderer/model/procedural.h"

#include "renderer/errors.h"
#include "renderer/io/volume_io.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace renderer {
namespace {

// Allocates an F32 volume after checking the size the caller asked for.
Volume makeVolume(const char* name, glm::ivec3 dims) {
    if (dims.x < 1 || dims.y < 1 || dims.z < 1)
        throw RenderError(std::string(name) + ": dims must be positive, got " + std::to_string(dims.x) + "x" +
                          std::to_string(dims.y) + "x" + std::to_string(dims.z));
    // In double so the product cannot wrap before it is compared.
    if (double(dims.x) * double(dims.y) * double(dims.z) > double(kMaxVoxels))
        throw RenderError(std::string(name) + ": more than " + std::to_string(kMaxVoxels) + " voxels");
    Volume volume;
    volume.name = name;
    volume.dims = dims;
    volume.values.floats().resize(volume.voxelCount());
    return volume;
}

} // namespace

Volume makeCheckerboard(glm::ivec3 dims, int cell) {
    if (cell < 1) throw RenderError("checkerboard: cell is " + std::to_string(cell) + ", expected >= 1");
    Volume volume = makeVolume("checkerboard", dims);
    std::vector<float>& values = volume.values.floats();
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                values[volume.index(x, y, z)] = float((x / cell + y / cell + z / cell) & 1);
    updateRange(volume);
    return volume;
}

Volume makeSphereShells(int n, double period, double thickness) {
    if (!(period > 0) || !std::isfinite(period) || !(thickness >= 0) || !std::isfinite(thickness))
        throw RenderError("sphere-shells: period must be positive and thickness non-negative, got period " +
                          std::to_string(period) + ", thickness " + std::to_string(thickness));
    Volume volume = makeVolume("sphere-shells", glm::ivec3(n));
    std::vector<float>& values = volume.values.floats();
    const double c = 0.5 * (n - 1);   // centre in voxel coordinates
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double dist = std::sqrt((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c));
                const double toShell = std::abs(dist - std::round(dist / period) * period);
                // 1 inside the shell, 0 outside, a linear ramp one voxel wide centred on its surface.
                values[volume.index(x, y, z)] =
                    float(std::clamp(0.5 + (0.5 * thickness - toShell), 0.0, 1.0));
            }
    updateRange(volume);
    return volume;
}

Volume makeMarschnerLobb(int n) {
    if (n < 2) throw RenderError("marschner-lobb: n is " + std::to_string(n) + ", expected >= 2");
    Volume volume = makeVolume("marschner-lobb", glm::ivec3(n));
    std::vector<float>& values = volume.values.floats();
    constexpr double kFm = 6.0, kAlpha = 0.25, kPi = std::numbers::pi;
    const auto coord = [n](int i) { return -1.0 + 2.0 * i / (n - 1); };   // voxel index -> [-1, 1]
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double px = coord(x), py = coord(y), pz = coord(z);
                const double rhoR =
                    std::cos(2.0 * kPi * kFm * std::cos(kPi * std::sqrt(px * px + py * py) / 2.0));
                const double rho =
                    (1.0 - std::sin(kPi * pz / 2.0) + kAlpha * (1.0 + rhoR)) / (2.0 * (1.0 + kAlpha));
                values[volume.index(x, y, z)] = float(rho);
            }
    updateRange(volume);
    return volume;
}

} // namespace renderer
