// What every loader fuzz target shares: the input is written to a file in a private scratch folder
// (next to a small "data.raw" that detached headers may name) and handed to a loader. A LoadError is
// the expected answer to a bad file; any other exception, a crash or a sanitizer report is a bug.
#pragma once
#include "renderer/errors.h"
#include "renderer/model/volume.h"
#include "renderer/io/volume_io.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace fuzz {

// /dev/shm when there is one (no disk writes per input), else the system temp folder; one per process.
inline const std::filesystem::path& scratchDir() {
    static const std::filesystem::path dir = [] {
        std::filesystem::path base = std::filesystem::exists("/dev/shm")
                                         ? std::filesystem::path("/dev/shm")
                                         : std::filesystem::temp_directory_path();
        std::filesystem::path d = base / ("splatlab_fuzz_" + std::to_string(getpid()));
        std::filesystem::create_directories(d);
        std::ofstream data(d / "data.raw", std::ios::binary);
        for (int i = 0; i < 4096; ++i)
            data.put(char(i * 7 % 251));
        return d;
    }();
    return dir;
}

inline std::filesystem::path writeInput(const std::string& name, const uint8_t* data, size_t size) {
    const std::filesystem::path path = scratchDir() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    out.close();
    return path;
}

// Loads and checks the invariants every successful load must hold.
template <class Load> void loadAndCheck(Load&& load) {
    try {
        const renderer::Volume v = load();
        if (v.values.size() != v.voxelCount() || v.dims.x < 1 || v.dims.y < 1 || v.dims.z < 1) std::abort();
        if (!(v.spacing.x > 0 && v.spacing.y > 0 && v.spacing.z > 0)) std::abort();
        if (v.voxelCount() > renderer::kMaxVoxels) std::abort();
        // Whatever axes the header gave, alignment keeps every voxel and leaves a rotation, or resamples
        // sheared axes onto a bounded grid along the world's (or refuses them with a LoadError).
        const renderer::Volume a = renderer::alignedToWorldAxes(v);
        if (a.values.size() != a.voxelCount() || a.dims.x < 1 || a.dims.y < 1 || a.dims.z < 1) std::abort();
        if (!a.resampled && a.voxelCount() != v.voxelCount()) std::abort();
        if (a.resampled && (a.directions != glm::dmat3(1.0) || a.voxelCount() > renderer::kMaxVoxels ||
                            a.voxelCount() > 8 * std::max<size_t>(v.voxelCount(), 1 << 17)))
            std::abort();
        if (!(a.spacing.x > 0 && a.spacing.y > 0 && a.spacing.z > 0)) std::abort();
        if (!renderer::isRotation(a.drawnAxes())) std::abort();
    } catch (const renderer::LoadError&) {
        // the expected answer to a malformed file
    }
}

} // namespace fuzz
