// `splatlab compare A B`: the error of image A against reference B (error.md's metric), and optionally
// their difference as an image.
#pragma once
#include <CLI/CLI.hpp>

#include <string>

struct CompareArgs {
    std::string image, reference, diff;
    double gain = 10.0;
};

CLI::App* addCompareCommand(CLI::App& app, CompareArgs& args);
int runCompare(const CompareArgs& args);
