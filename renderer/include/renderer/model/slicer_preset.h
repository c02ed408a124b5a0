// 3D Slicer's volume-rendering presets (its presets.xml, an MRML file): one <VolumeProperty> element per
// preset, whose attributes hold the functions as counted number lists in data units:
//   scalarOpacity="N x1 o1 x2 o2 ..."   colorTransfer="N x1 r1 g1 b1 ..."   gradientOpacity="N g1 o1 ..."
// (N counts the numbers after it). Read into a TransferFunction; nothing is written. No XML library: a
// careful attribute reader for this one element is all the format needs.
#pragma once
#include "renderer/model/transfer_function.h"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace renderer {

struct SlicerPreset {
    // Name, colour, scalar opacity and gradient opacity, in data units. Slicer's gradient magnitudes are
    // VTK's, in data units per world unit (mm), as ours; a gradient opacity of 1 everywhere is left out.
    TransferFunction tf;
};

// Every <VolumeProperty> of `text`, in file order (elements inside XML comments are skipped). Throws
// LoadError naming `source`, the preset and the attribute for a missing attribute, a count that does not
// match its numbers, a number that is not one (or not finite), positions out of order, a colour or
// opacity outside [0,1], or a text with no preset at all.
std::vector<SlicerPreset> slicerPresetsFromXml(std::string_view text, const std::string& source);
std::vector<SlicerPreset> loadSlicerPresets(const std::filesystem::path& path);


// A Slicer preset file named in a TF spec: "FILE.xml" (the file's first preset) or "FILE.xml#NAME".
struct SlicerPresetSpec {
    std::filesystem::path file;
    std::string name; // empty: the first preset
};
std::optional<SlicerPresetSpec> slicerPresetSpec(const std::string& spec);

// The preset a spec names, and what the user should know about it: that the first of several was taken.
// Throws LoadError listing the file's presets for an unknown name.
struct LoadedSlicerPreset {
    SlicerPreset preset;
    std::vector<std::string> notes; // one line each
};
LoadedSlicerPreset loadSlicerPreset(const SlicerPresetSpec& spec);

} // namespace renderer
