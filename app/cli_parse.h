// Parsing the command line's values (sizes, cameras, numbers) into the renderer's types, with errors
// that name the flag; shared by main.cpp and the commands in files of their own.
#pragma once
#include "renderer/math/camera.h"

#include <string>
#include <vector>

std::string formatRange(double lo, double hi); // "in [lo, hi]", for a flag's range
std::vector<std::string> splitOn(const std::string& s, char sep);
// `text` as a finite number, or CLI::ValidationError naming `flag` and `what` the number is.
double parseNumber(const std::string& text, const std::string& flag, const std::string& what);
glm::ivec2 parseSize(const std::string& text, const std::string& flag); // "WxH", 1..16384 each
renderer::Camera parseCamera(const std::string& text);                  // "azimuth,elevation,distance,fov"
