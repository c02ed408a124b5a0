// `splatlab info VOLUME`: a volume's dims, type, spacing, origin, axes (and how the tools draw them), value
// range, p1..p99 window, a 16-bin histogram and, with --gradients, the gradient magnitudes.
#pragma once
#include "renderer/io/volume_io.h"

#include <optional>
#include <string>

int runInfo(const std::string& path, const std::optional<renderer::RawOptions>& raw, bool gradients);
