// Hard-case scenes (see hard_cases.h). Each volume is analytic or tiny, so a case needs no data files.
#include "renderer/oracle/hard_cases.h"

#include "renderer/model/procedural.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace renderer {

namespace {

TransferFunction ramp(const char* name, double opacity) {
    return fromSharedPoints(name, {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.3, {0.3, 0.9, 0.4}, 0.3 * opacity}, {1.0, {1.0, 0.8, 0.3}, opacity}});
}

TransferFunction solid(double opacity) {
    return fromSharedPoints("solid", {{0.0, {0.9, 0.9, 0.9}, opacity}, {1.0, {0.9, 0.9, 0.9}, opacity}});
}

TransferFunction binary() {   // 0 transparent, 1 opaque white: checkerboards and zebras
    return fromSharedPoints("binary",
                            {{0.0, {0, 0, 0}, 0.0}, {0.49, {0, 0, 0}, 0.0}, {0.51, {1, 1, 1}, 1.0}, {1.0, {1, 1, 1}, 1.0}});
}

Volume zebra(int n, int period) {
    Volume v;
    v.name = "zebra";
    v.dims = {n, n, n};
    v.type = VoxelType::F32;
    std::vector<float>& values = v.values.floats();
    values.resize(v.voxelCount());
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) values[v.index(x, y, z)] = float((x / period) % 2);
    updateRange(v);
    return v;
}

// A 9^3 field of v(distance d from the centre voxel, x): the ramp 1 - d / 7 tilted along x, or a ball.
Volume ninePattern(const char* name, bool ball) {
    Volume v;
    v.name = name;
    v.dims = {9, 9, 9};
    v.type = VoxelType::F32;
    std::vector<float>& values = v.values.floats();
    values.resize(v.voxelCount());
    for (int z = 0; z < 9; ++z)
        for (int y = 0; y < 9; ++y)
            for (int x = 0; x < 9; ++x) {
                const double d = std::sqrt(double((x - 4) * (x - 4) + (y - 4) * (y - 4) + (z - 4) * (z - 4)));
                values[v.index(x, y, z)] =
                    ball ? float(d <= 4.0) : float(std::clamp(1.0 - d / 7.0 + 0.02 * (x - 4), 0.0, 1.0));
            }
    updateRange(v);
    return v;
}

} // namespace

std::vector<HardCase> nearEyeCases() {
    std::vector<HardCase> cases(2);
    cases[0].name = "voxel-centre";
    cases[0].what = "the camera on a voxel centre inside a volume";
    cases[0].volume = ninePattern("ramp9", false);
    cases[0].tf = ramp("ramp", 0.8);
    cases[0].camera = {30, 20, 1e-3, 60.0};
    cases[1].name = "thin-ball";
    cases[1].what = "the camera inside an optically thin ball";
    cases[1].volume = ninePattern("ball9", true);
    cases[1].tf = fromSharedPoints("thin", {{0.0, {0.9, 0.6, 0.3}, 0.0},
                                            {0.49, {0.9, 0.6, 0.3}, 0.0},
                                            {0.51, {0.9, 0.6, 0.3}, 0.15},
                                            {1.0, {0.9, 0.6, 0.3}, 0.15}});
    cases[1].camera = {30, 20, 0.3, 60.0};
    return cases;
}

std::vector<HardCase> hardCases(int scale, const std::string& only) {
    const int s = std::max(scale, 1);
    const int img = 48 * s;
    std::vector<HardCase> cases;
    // Volumes are built only for the cases asked for: a demo scene wants one of them, not all.
    auto add = [&](std::string name, std::string what, auto makeVolume, TransferFunction tf, Camera cam) {
        if (!only.empty() && name != only) return;
        HardCase c;
        c.name = std::move(name);
        c.what = std::move(what);
        c.volume = makeVolume();
        c.tf = std::move(tf);
        c.camera = cam;
        c.width = c.height = img;
        cases.push_back(std::move(c));
    };

    add("near-plane", "camera inside the volume: voxels at and behind the near plane",
        [&] { return makeSphereShells(10 * s, 4.0 * s, 1.5 * s); }, ramp("ramp", 0.6), {30, 20, 0.45, 90.0});
    add("far-away", "volume 3 px across: sub-pixel footprints must not vanish", [&] { return makeMarschnerLobb(12 * s); },
        ramp("ramp", 1.0), {30, 20, 60.0, 30.0});
    add("grazing-checkerboard", "000 fig. 8: checkerboard slab seen at 4 degrees, magnified to minified",
        [&] { return makeCheckerboard({64 * s, 64 * s, 3}, 4); }, binary(), {10, 4, 1.1, 40.0});
    add("anisotropic-1-100", "spacing 1:1:100: needle-like kernels",
        [&] {
            Volume v = makeMarschnerLobb(12 * s);
            v.spacing = {1.0, 1.0, 100.0};
            return v;
        },
        ramp("ramp", 0.5), {40, 30, 2.2, 30.0});
    add("zebra", "001 fig. 8: stripes at the grid's highest frequency, minified", [&] { return zebra(16 * s, 1); },
        binary(), {0, 10, 6.0, 30.0});
    add("marschner-lobb", "the standard reconstruction test signal", [&] { return makeMarschnerLobb(16 * s); },
        ramp("ramp", 0.8), {30, 20, 2.5, 30.0});
    add("huge-coordinates", "volume 1e6 units from the origin (float precision)",
        [&] {
            Volume v = makeMarschnerLobb(12 * s);
            v.origin = {1e6, -1e6, 1e6};
            return v;
        },
        ramp("ramp", 0.8), {30, 20, 2.5, 30.0});
    add("fov-1", "1 degree field of view (nearly parallel rays)", [&] { return makeMarschnerLobb(12 * s); },
        ramp("ramp", 0.8), {30, 20, 75.0, 1.0});
    add("fov-170", "170 degree field of view: strong off-axis distortion", [&] { return makeMarschnerLobb(12 * s); },
        ramp("ramp", 0.8), {30, 20, 1.2, 170.0});
    {
        Camera c{30, 20, 2.5, 30.0};
        c.orthographic = true;
        add("orthographic", "parallel projection: the constant affine map", [&] { return makeMarschnerLobb(12 * s); },
            ramp("ramp", 0.8), c);
    }
    add("thin-slices", "48 slices of 1 % opacity each: accumulation precision",
        [&] { return makeCheckerboard({16 * s, 16 * s, 48 * s}, 1024); },   // one cell: constant 0
        solid(0.01), {0, 80, 2.5, 30.0});
    add("nan-inf-values", "every 7th voxel NaN, every 11th +Inf",
        [&] {
            Volume v = makeMarschnerLobb(10 * s);
            std::vector<float>& values = v.values.floats();
            for (size_t i = 0; i < values.size(); i += 7) values[i] = std::numeric_limits<float>::quiet_NaN();
            for (size_t i = 3; i < values.size(); i += 11) values[i] = std::numeric_limits<float>::infinity();
            updateRange(v);
            return v;
        },
        ramp("ramp", 0.8), {30, 20, 2.5, 30.0});
    add("constant-volume", "every voxel the same value (empty value range)",
        [&] { return makeCheckerboard({8 * s, 8 * s, 8 * s}, 1024); },   // constant 0
        solid(0.3), {30, 20, 2.5, 30.0});
    add("one-voxel", "a single voxel (zero bounding radius)",
        [] {
            Volume v;
            v.name = "one-voxel";
            v.dims = {1, 1, 1};
            v.values = {1.0f};
            v.range = {1.0f, 1.0f};
            return v;
        },
        solid(0.8), {30, 20, 2.5, 30.0});
    return cases;
}

} // namespace renderer
