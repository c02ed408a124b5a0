// The HTML page `splatlab report` writes: a section per scan with its speed-against-error chart (inline
// SVG from ui's chart layout), a table of the figures and the thumbnails; and the same tables as
// markdown, for docs/speed.md and the README. Text only; no I/O.
#pragma once
#include "renderer/oracle/filter_comparison.h"

#include <span>
#include <string>
#include <vector>

struct ReportSection {
    std::string name; // the scan's file name
    std::string view; // size, TF and camera, in words
    std::string brief; // voxels and TF, for the summary table
    std::vector<renderer::FilterMeasurement> points;
    renderer::SplatSettings current;     // the settings the others vary from (ringed)
    std::string viewImage, truthImage;   // thumbnails beside index.html
    std::vector<std::string> cropImages; // one per point
    int cropWidth = 0, cropHeight = 0;   // px of the view's centre the errors are over
};

struct ReportPage {
    std::vector<ReportSection> sections;
    std::string glRenderer, machine;
    int repeats = 0;
    double seconds = 0.0;
};

// The chart as an SVG element, `width` x `height` px. Each point is a <g class="point"> with its
// figures as data- attributes and its marker placed by transform="translate(x,y)".
std::string speedErrorSvg(std::span<const renderer::FilterMeasurement> points,
                          const renderer::SplatSettings& current, int width, int height);
std::string reportHtml(const ReportPage& page);
// A table per scan: each setting's median frame time with its p10-p90, PSNR and whether it is on the
// Pareto front, under a line naming GL_RENDERER, the machine and the repeats.
std::string reportMarkdown(const ReportPage& page);
// One table for the README: a row per scan with each filter's median frame time and PSNR, sheets front
// to back, and the settings on the Pareto front.
std::string reportSummaryMarkdown(const ReportPage& page);
