// Transfer function: a colour function and an opacity function, each piecewise linear over its own
// points, positioned in the data's units (HU for CT) -> an RGBA lookup table over the scene's window;
// optionally a gradient opacity function (|gradient| -> a factor on the opacity, as ParaView and Slicer).
// Opacity is extinction per unit length (EWA_NOTES): a point's `opacity` times SplatSettings::density
// is the extinction per voxel length. Files and presets are JSON (docs/formats.md); the points are saved.
#pragma once
#include "renderer/math/glm_config.h"
#include "renderer/model/volume.h"

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace renderer {

struct ColourPoint {
    double value = 0.0;        // position (data units, or a fraction of the window: TransferFunction)
    glm::dvec3 colour{1.0};    // linear RGB in [0,1]
    bool operator==(const ColourPoint&) const = default;
};

struct OpacityPoint {
    double value = 0.0;        // position, as ColourPoint::value
    double opacity = 0.0;      // in [0,1]; 0 makes voxels of this value invisible (never drawn)
    bool operator==(const OpacityPoint&) const = default;
};

// A point of the gradient opacity function (ParaView's and Slicer's "gradient opacity").
struct GradientOpacityPoint {
    double magnitude = 0.0;    // |gradient| in data units per world unit (gradients.h: HU/mm for a CT in mm)
    double opacity = 1.0;      // factor in [0,1] on the opacity of voxels with this gradient magnitude
    bool operator==(const GradientOpacityPoint&) const = default;
};

// A widget of the 2D transfer function (value x gradient magnitude; Kniss et al. 2001): a shape in that
// plane with a weight in [0,1] at each point, and the colour and opacity it gives there (evaluate2d).
enum class WidgetShape { Rectangle, Triangle };
struct Widget2D {
    WidgetShape shape = WidgetShape::Rectangle;
    // Rectangle: weight 1 on value [valueLo, valueHi] x magnitude [magnitudeLo, magnitudeHi], edges
    // included, 0 outside. Triangle (the boundary widget): apex at (apex, magnitude 0), widening with
    // magnitude to half-width halfWidth at magnitudeTop; weight 1 on its centre line (value = apex),
    // falling linearly to 0 at its sides, 0 above magnitudeTop. Values in data units (always: a TF in
    // window fractions keeps its widgets in data units), magnitudes in data units per world unit.
    double valueLo = 0.0, valueHi = 0.0, magnitudeLo = 0.0, magnitudeHi = 0.0;   // rectangle
    double apex = 0.0, halfWidth = 0.0, magnitudeTop = 0.0;                      // triangle
    glm::dvec3 colour{1.0};    // linear RGB in [0,1]
    double opacity = 1.0;      // in [0,1], as OpacityPoint::opacity, at weight 1
    bool operator==(const Widget2D&) const = default;
};

struct TransferFunction {
    std::string name;
    std::vector<ColourPoint> colours;      // sorted by value; piecewise linear between them
    std::vector<OpacityPoint> opacities;   // sorted by value; piecewise linear between them
    // Sorted by magnitude; piecewise linear, its end points' own outside them. Empty: a factor of 1 at
    // every gradient (no gradient opacity). Always in data units per world unit (windowFractions, Shift
    // and Rescale move the value axis only).
    std::vector<GradientOpacityPoint> gradientOpacity;
    // True for version-1 files and the built-in presets: positions are 0..1 of whichever window the TF
    // meets (0 = window.lo). inDataUnits() fixes them over one window; the editor does so when it takes
    // the TF, so a later window change no longer moves it.
    bool windowFractions = false;
    // The 2D transfer function: with any widget, each voxel's colour and opacity come from its value and
    // gradient magnitude (evaluate2d) instead of the curves and the gradient opacity above, which stay
    // (and decide again once the last widget is removed). Applies once the scene has gradients.
    std::vector<Widget2D> widgets2d;
    bool operator==(const TransferFunction&) const = default;
};

// A version-1 point: colour and opacity at one shared position, a fraction of the window. The built-in
// presets and tests are written this way; fromSharedPoints splits them into the two functions.
struct ControlPoint {
    double value = 0.0;
    glm::dvec3 colour{1.0};
    double opacity = 0.0;
};
TransferFunction fromSharedPoints(std::string name, const std::vector<ControlPoint>& points);

// Entries of the lookup table both the CPU oracle and the GL path index with a voxel's class.
constexpr int kLutSize = 4096;
using Lut = std::vector<glm::vec4>;     // kLutSize entries: rgb colour, a = opacity

// Colour (rgb) and opacity (a) at `value` (the TF's own units): each linear between its points around
// it, its end points' own outside them (black, transparent with no points).
glm::dvec4 evaluate(const TransferFunction& tf, double value);
// The gradient opacity factor at `magnitude` (data units per world unit): 1 without gradient points.
double evaluateGradientOpacity(const TransferFunction& tf, double magnitude);
// A widget's weight at (value, magnitude), in [0,1] (Widget2D).
double widgetWeight(const Widget2D& w, double value, double magnitude);
// The 2D TF at (value data units, magnitude): opacity the largest weight x opacity of the widgets, colour
// the mean of their colours weighted by weight x opacity (black where none reaches). The largest, not a
// sum: overlapping widgets do not add up to more than either asks, and the order does not matter.
glm::dvec4 evaluate2d(const TransferFunction& tf, double value, double magnitude);

// The LUT spans `window`, the scene's classification range (classOf): entry i is the TF at the data
// value in the middle of class i. Why the window and not the TF's extent: a voxel's class then does not
// depend on the TF, so a TF edit re-bakes these 4096 entries and nothing else (the editor's drag stays
// instant), and the classes are finest where the user looks. Values outside the window read its end
// classes, so the TF's own end values whenever its points lie inside the window, as every version-1 TF's
// do (their 0 and 1 are the window's ends); a TF reaching past the window shows, beyond it, its value at
// the window's edge: widen the window to see the rest.
Lut bakeLut(const TransferFunction& tf, ValueRange window);
// Class of a value: which LUT entry it reads. Normalises over [lo, hi] and clamps; NaN gets class 0.
uint16_t classOf(float value, float lo, float hi);

// == Whole-TF edits (pure; the TF panel's Shift and Rescale)

// The TF with window fractions turned into data units over `window` (unchanged if already in data units
// or the window is empty). Fraction 0 gives window.lo and 1 window.hi exactly.
TransferFunction inDataUnits(const TransferFunction& tf, ValueRange window);
// The lowest and highest position of any colour or opacity point or widget value ({0, 0} with none).
struct TfExtent {
    double lo = 0.0, hi = 0.0;
};
TfExtent extentOf(const TransferFunction& tf);
// Every point and widget moved by `offset` along the value axis (the TF's units).
TransferFunction shifted(const TransferFunction& tf, double offset);
// The TF's extent mapped linearly onto [lo, hi] (lo < hi): its first point lands on lo, its last on hi,
// the rest (widgets' values and widths too) in proportion. A TF whose points all sit at one value is moved to the middle of [lo, hi].
// Throws RenderError for a non-finite or empty target.
TransferFunction rescaled(const TransferFunction& tf, double lo, double hi);

// Presets by name: those in code ("ct-skin-bone", "ct-bone", "grey-ramp", "soft", "fire"; window
// fractions), then each NAME.json of the bundled assets/presets ("bonsai", "ct-hu-skin-bone"), sorted.
std::vector<std::string> builtinPresetNames();
// Throws RenderError listing the names if unknown, LoadError naming the file if a bundled one is bad.
TransferFunction builtinPreset(const std::string& name);
// A SplatLab TF file, or a ParaView preset (paraview_preset.h), whichever the JSON is. Throws LoadError.
TransferFunction loadTransferFunction(const std::filesystem::path& path);
void saveTransferFunction(const TransferFunction& tf, const std::filesystem::path& path);  // atomic
std::string transferFunctionText(const TransferFunction& tf);   // what saveTransferFunction writes
// The JSON of a TF file (version 2), and back (version 1 or 2; sessions embed it): `source` names the
// file in errors, and `defaultName` is the name when the JSON gives none. Throws LoadError naming the field.
nlohmann::json toJson(const TransferFunction& tf);
TransferFunction transferFunctionFromJson(const nlohmann::json& j, const std::string& source,
                                          const std::string& defaultName);
// A preset name, a JSON file path, or a 3D Slicer presets file ("FILE.xml" or "FILE.xml#NAME",
// slicer_preset.h), whichever `spec` is. `notes`, when given, gets a line for what an import leaves out.
TransferFunction transferFunctionFromSpec(const std::string& spec, std::vector<std::string>* notes = nullptr);

} // namespace renderer
