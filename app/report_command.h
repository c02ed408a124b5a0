// `splatlab report VOLUME... --out DIR`: speed against error for each scan, as a self-contained page
// (DIR/index.html with SVG charts, tables and PNG thumbnails beside it). The measurement is renderer's
// (speed_error.h), the chart's layout ui's (speed_error_chart.h); this loads, measures and writes.
#pragma once
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

struct ReportArgs {
    std::vector<std::string> volumes;
    std::string out;              // DIR: index.html and the thumbnails
    int repeats = 5;              // timed frames per setting
    std::string size = "256x256"; // the view measured; errors are over its centre crop
    std::string camera = "30,20,2.5,30";
    std::string up = "z";   // the axis shown upwards: one for every volume, or one per volume (y,z,-z)
    std::string tf;    // empty: the preset named like the volume (bonsai, headsq), else ct-skin-bone
    std::string cache; // ground-truth cache (empty: the default, ground_truth.h)
    double slabThickness = 0.0;   // --image-slabs: also time these image-aligned slabs (0: none)
    bool postClassify = false;    // --post-classify: the slabs post-classified, against their own truth
};

CLI::App* addReportCommand(CLI::App& app, ReportArgs& args);
int runReport(const ReportArgs& args);
