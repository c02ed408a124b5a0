// Parsing the command line's values (sizes, cameras, numbers) into the renderer's types, with errors
// that name the flag; shared by main.cpp and the commands in files of their own.
#pragma once
#include "renderer/math/camera.h"
#include "renderer/model/splat_settings.h"
#include "ui/split_view.h"

#include <string>
#include <vector>

std::string formatRange(double lo, double hi); // "in [lo, hi]", for a flag's range
std::vector<std::string> splitOn(const std::string& s, char sep);
// `text` as a finite number, or CLI::ValidationError naming `flag` and `what` the number is.
double parseNumber(const std::string& text, const std::string& flag, const std::string& what);
glm::ivec2 parseSize(const std::string& text, const std::string& flag); // "WxH", 1..16384 each
renderer::Camera parseCamera(const std::string& text);                  // "azimuth,elevation,distance,fov"
// --split: "" (no split), or two or four filter names, "A,B" or "A,B,C,D"; any other count, or a name it
// does not know, a CLI::ValidationError naming the flag.
std::vector<renderer::FilterMode> parseSplit(const std::string& text);
// --split-difference's value: none (|A - B|) or "truth" (|A - ground truth|); `split`: --split was given.
ui::SplitDifference parseSplitDifference(const std::string& text, bool split);
