// `splatlab phantom` (see phantom_command.h): parses the size, makes the phantom, writes it, and prints
// what was written and how long each step took.
#include "phantom_command.h"

#include "renderer/io/atomic_file.h"
#include "renderer/io/nrrd_writer.h"
#include "renderer/model/phantom.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

namespace {

using namespace renderer;
namespace fs = std::filesystem;

// "512" -> 512^3; "512x512x400" -> as given.
glm::ivec3 parseDims(const std::string& text) {
    std::vector<std::string> parts;
    std::stringstream in(text);
    for (std::string p; std::getline(in, p, 'x');)
        parts.push_back(p);
    const auto bad = [&] {
        return CLI::ValidationError("--size", "'" + text +
                                                  "': expected N or WxHxD of positive integers, e.g. 512 or "
                                                  "512x512x400");
    };
    if (parts.size() != 1 && parts.size() != 3) throw bad();
    glm::ivec3 dims(0);
    for (int axis = 0; axis < 3; ++axis) {
        const std::string& p = parts[parts.size() == 1 ? 0 : size_t(axis)];
        if (p.empty() || p.size() > 6 || p.find_first_not_of("0123456789") != std::string::npos) throw bad();
        dims[axis] = std::stoi(p);
        if (dims[axis] < 1) throw bad();
    }
    return dims;
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

CLI::App* addPhantomCommand(CLI::App& app, PhantomArgs& a) {
    auto* cmd =
        app.add_subcommand("phantom", "Write a CT-like head phantom (int16 HU: air, skin, soft tissue, "
                                      "skull, brain, noise) as NRRD test data");
    cmd->add_option("--size", a.size, "N (a cube) or WxHxD voxels; the head fills a 256 mm cube at any size")
        ->capture_default_str();
    cmd->add_option("--seed", a.seed, "Seed of the noise (same seed and size: same voxels)")
        ->capture_default_str();
    cmd->add_option("--noise", a.noiseHu, "Standard deviation of the Gaussian noise, HU (0: none)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1000.0));
    cmd->add_option("--out", a.out, "Output: FILE.nhdr (header + FILE.raw beside it) or FILE.nrrd (one file)")
        ->required();
    cmd->add_flag("--gzip", a.gzip, "Compress the voxels (NRRD encoding gzip; FILE.raw.gz for .nhdr)");
    return cmd;
}

int runPhantom(const PhantomArgs& a) {
    // 1. Flags and the output, checked before the seconds of generation.
    PhantomOptions options;
    options.dims = parseDims(a.size);
    options.seed = a.seed;
    options.noiseHu = a.noiseHu;
    const fs::path out = a.out;
    if (out.extension() != ".nhdr" && out.extension() != ".nrrd")
        throw CLI::ValidationError("--out", "'" + a.out + "': expected a .nhdr or .nrrd file name");
    checkFileReplaceable(out);

    // 2. Generate, then write.
    auto t0 = std::chrono::steady_clock::now();
    const Volume phantom = makePhantom(options);
    const double generateS = secondsSince(t0);
    t0 = std::chrono::steady_clock::now();
    const std::vector<fs::path> files = saveNrrd(phantom, out, {.gzip = a.gzip});
    const double writeS = secondsSince(t0);

    // 3. Report: what, where, how big, how long.
    std::string names;
    uintmax_t onDisk = 0;
    for (const fs::path& f : files) {
        names += (names.empty() ? "" : ", ") + f.string();
        onDisk += fs::file_size(f);
    }
    const glm::dvec3 s = phantom.spacing;
    std::printf(
        "%s: phantom %d x %d x %d int16 HU, spacing %g x %g x %g mm (a %g mm cube), seed %u, noise %g HU\n",
        names.c_str(), phantom.dims.x, phantom.dims.y, phantom.dims.z, s.x, s.y, s.z, kPhantomFieldMm,
        options.seed, options.noiseHu);
    std::printf(
        "  HU %g .. %g, %zu bytes of voxels, %ju bytes on disk; generated in %.2f s, written in %.2f s\n",
        phantom.range.lo, phantom.range.hi, phantom.voxelCount() * sizeof(int16_t), onDisk, generateS,
        writeS);
    return 0;
}
