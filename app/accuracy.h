// `splatlab accuracy`: measures every filter mode against the ground truth and writes docs/accuracy.md
// with its thumbnails. The measurements are renderer's (accuracy.h, hard_cases.h); this owns the report.
#pragma once
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

struct AccuracyArgs {
    std::string out = "docs";      // writes OUT/accuracy.md and OUT/images/accuracy/*.png
    std::string cache;             // ground-truth cache (empty: the default, ground_truth.h)
    std::vector<std::string> only; // hard cases to run (empty: all)
    int board = 512;               // grazing checkerboard side; the image is board/4 x board/8
    int marschnerLobb = 16;        // Marschner-Lobb samples per axis for the kernel-scale sweep
    std::vector<double> kernelScales{0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
};

CLI::App* addAccuracyCommand(CLI::App& app, AccuracyArgs& args);
int runAccuracy(const AccuracyArgs& args);
