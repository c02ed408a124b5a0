// `splatlab phantom`: writes the CT-like head phantom (renderer/model/phantom.h) as an int16 NRRD, real-size
// test data for the benchmark and the editor. The anatomy is renderer's; this owns the flags and the report.
#pragma once
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

struct PhantomArgs {
    std::string size = "512"; // N (a cube) or WxHxD
    uint32_t seed = 1;
    double noiseHu = 20.0;
    std::string out; // .nhdr (header + NAME.raw[.gz]) or .nrrd (one file)
    bool gzip = false;
};

CLI::App* addPhantomCommand(CLI::App& app, PhantomArgs& args);
int runPhantom(const PhantomArgs& args);
