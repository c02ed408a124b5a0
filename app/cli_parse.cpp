// Command-line values into the renderer's types (cli_parse.h).
#include "cli_parse.h"

#include "renderer/errors.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

using renderer::Camera;
using renderer::kMaxCameraDistance;
using renderer::kMinCameraDistance;

std::string formatRange(double lo, double hi) {
    char text[64];
    std::snprintf(text, sizeof text, "in [%g, %g]", lo, hi);
    return text;
}

std::vector<std::string> splitOn(const std::string& s, char sep) {
    std::vector<std::string> parts;
    std::stringstream in(s);
    for (std::string p; std::getline(in, p, sep);)
        parts.push_back(p);
    return parts;
}

double parseNumber(const std::string& text, const std::string& flag, const std::string& what) {
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || !std::isfinite(v))
        throw CLI::ValidationError(flag, "'" + text + "' is not a number (" + what + ")");
    return v;
}

glm::ivec2 parseSize(const std::string& text, const std::string& flag) {
    const auto parts = splitOn(text, 'x');
    if (parts.size() != 2) throw CLI::ValidationError(flag, "'" + text + "': expected WxH, e.g. 512x512");
    const int w = int(parseNumber(parts[0], flag, "width")), h = int(parseNumber(parts[1], flag, "height"));
    if (w < 1 || h < 1 || w > 16384 || h > 16384)
        throw CLI::ValidationError(flag, "'" + text + "': width and height must be 1..16384");
    return {w, h};
}

Camera parseCamera(const std::string& text) {
    const auto parts = splitOn(text, ',');
    if (parts.size() != 4)
        throw CLI::ValidationError("--camera", "'" + text +
                                                   "': expected azimuth,elevation,distance,fov (degrees, "
                                                   "bounding radii, degrees), e.g. 30,20,2.5,30");
    Camera c;
    c.azimuthDeg = parseNumber(parts[0], "--camera", "azimuth");
    c.elevationDeg = parseNumber(parts[1], "--camera", "elevation");
    c.distance = parseNumber(parts[2], "--camera", "distance");
    c.fovYDeg = parseNumber(parts[3], "--camera", "fov");
    if (c.elevationDeg < -89.9 || c.elevationDeg > 89.9)
        throw CLI::ValidationError("--camera", "elevation must be within -89.9..89.9 degrees");
    if (!(c.distance >= kMinCameraDistance && c.distance <= kMaxCameraDistance))
        throw CLI::ValidationError("--camera", "distance must be " +
                                                   formatRange(kMinCameraDistance, kMaxCameraDistance) +
                                                   " bounding radii");
    if (!(c.fovYDeg >= 1 && c.fovYDeg <= 170))
        throw CLI::ValidationError("--camera", "fov must be 1..170 degrees");
    return c;
}

std::vector<renderer::FilterMode> parseSplit(const std::string& text) {
    if (text.empty()) return {};
    const std::vector<std::string> names = splitOn(text, ',');
    const size_t commas = size_t(std::count(text.begin(), text.end(), ','));
    if ((commas != 1 && commas != 3) || names.size() != commas + 1)
        throw CLI::ValidationError("--split", "expected two or four filters, FILTER_A,FILTER_B or "
                                              "FILTER_A,FILTER_B,FILTER_C,FILTER_D, got '" +
                                                  text + "' (" + std::to_string(commas + 1) + " names)");
    std::vector<renderer::FilterMode> filters;
    try {
        for (const std::string& name : names)
            filters.push_back(renderer::filterModeFromName(name));
    } catch (const renderer::RenderError& error) {
        throw CLI::ValidationError("--split", error.what());
    }
    return filters;
}

ui::SplitDifference parseSplitDifference(const std::string& text, bool split) {
    if (!split) throw CLI::ValidationError("--split-difference", "needs --split A,B (or A,B,C,D)");
    if (text.empty() || text == "b") return ui::SplitDifference::AgainstB;
    if (text == "truth") return ui::SplitDifference::AgainstTruth;
    throw CLI::ValidationError("--split-difference",
                               "expected nothing (|A - B|) or 'truth' (|A - ground truth|), got '" + text +
                                   "'");
}
