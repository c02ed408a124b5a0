// Window/level: which data values map onto the transfer function's [0, 1] domain. The window is a
// ValueRange in the data's own units (Hounsfield units for CT, whatever a float simulation holds);
// buildSplatScene() takes it. Nothing here knows about files or GL.
#pragma once
#include "renderer/model/volume.h"

#include <string>

namespace renderer {

enum class WindowMode {
    DataRange,  // the volume's min..max
    Percentile, // the 1st..99th percentile of the finite values: outliers do not squash the rest
    Custom,     // lo..hi given in data units
};
const char* windowModeName(WindowMode mode); // "data range", "percentile 1-99", "custom"
WindowMode windowModeFromName(const std::string& name);   // throws RenderError listing the names

struct WindowSettings {
    WindowMode mode = WindowMode::DataRange;
    ValueRange custom; // used in Custom mode; data units, lo < hi
};

// The values at the `loPercent` and `hiPercent` percentiles (0..100) of the finite voxels, by rank
// (nearest rank, no interpolation: the result is always a value the volume holds). Throws RenderError
// for percentages outside 0..100 or lo > hi. An empty or all-NaN volume gives {0, 0}.
ValueRange percentileWindow(const Volume& volume, double loPercent, double hiPercent);
// The window a mode selects. Custom windows must have finite lo < hi (RenderError otherwise).
ValueRange windowFor(const Volume& volume, const WindowSettings& settings);

} // namespace renderer
