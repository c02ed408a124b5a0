// Transfer functions with colour and opacity functions of their own, in data units: the version-2 file
// and reading version 1, window fractions fixed over a window, the LUT over the window, Shift and Rescale.
#include "renderer/errors.h"
#include "renderer/model/procedural.h"
#include "renderer/model/splat_scene.h"
#include "renderer/model/transfer_function.h"
#include "test_paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

using namespace renderer;
using testing::HasSubstr;

namespace {

// A CT-like TF in HU whose colour stops and opacity points sit at different values.
TransferFunction hounsfield() {
    TransferFunction tf;
    tf.name = "hu";
    tf.colours = {{-1000.0, {0, 0, 0}}, {-250.0, {0.85, 0.6, 0.5}}, {1500.0, {1, 1, 1}}};
    tf.opacities = {{-1000.0, 0.0}, {-500.0, 0.0}, {-400.0, 0.02}, {-300.0, 0.0}, {300.0, 0.0}, {700.0, 0.8}};
    return tf;
}

std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto path = testing_support::testOutputDir("tf_files") / name;
    std::ofstream(path) << text;
    return path;
}

} // namespace

TEST(TransferFunctionFile, VersionTwoRoundTripsColourAndOpacityPointsInDataUnits) {
    const TransferFunction tf = hounsfield();
    const auto path = testing_support::testOutputDir("tf_files") / "hu.json";
    saveTransferFunction(tf, path);
    EXPECT_EQ(loadTransferFunction(path), tf);   // every point, exactly (JSON keeps a double's digits)
    const std::string text = transferFunctionText(tf);
    EXPECT_THAT(text, HasSubstr("\"version\": 2"));
    EXPECT_THAT(text, HasSubstr("\"units\": \"data\""));
    EXPECT_THAT(text, HasSubstr("-400.0"));   // positions in HU, not window fractions

    // A TF still in window fractions says so, and reads back as one.
    const TransferFunction preset = builtinPreset("ct-bone");
    saveTransferFunction(preset, path);
    EXPECT_THAT(transferFunctionText(preset), HasSubstr("\"units\": \"window fraction\""));
    EXPECT_EQ(loadTransferFunction(path), preset);
}

TEST(TransferFunctionFile, VersionOneSharedPointsSplitIntoTheTwoFunctionsOverTheWindow) {
    const auto path = write("old.json", R"({"version": 1, "name": "old", "points": [
        {"value": 0.0, "colour": [0, 0, 0], "opacity": 0.0},
        {"value": 0.5, "colour": [1, 0, 0], "opacity": 0.25},
        {"value": 1.0, "colour": [1, 1, 1], "opacity": 1.0}]})");
    const TransferFunction tf = loadTransferFunction(path);
    EXPECT_TRUE(tf.windowFractions);
    ASSERT_EQ(tf.colours.size(), 3u);
    ASSERT_EQ(tf.opacities.size(), 3u);
    EXPECT_EQ(tf.colours[1], (ColourPoint{0.5, {1, 0, 0}}));
    EXPECT_EQ(tf.opacities[1], (OpacityPoint{0.5, 0.25}));
    // A file from before the version field reads the same.
    EXPECT_EQ(loadTransferFunction(write("older.json", R"({"name": "old", "points": [
        {"value": 0.0, "colour": [0, 0, 0], "opacity": 0.0},
        {"value": 0.5, "colour": [1, 0, 0], "opacity": 0.25},
        {"value": 1.0, "colour": [1, 1, 1], "opacity": 1.0}]})")),
              tf);
    // Fixed over a window: 0 and 1 become its ends exactly, 0.5 its middle.
    const TransferFunction hu = inDataUnits(tf, {-1000.0f, 3000.0f});
    EXPECT_FALSE(hu.windowFractions);
    EXPECT_EQ(hu.colours.front().value, -1000.0);
    EXPECT_EQ(hu.opacities.back().value, 3000.0);
    EXPECT_DOUBLE_EQ(hu.opacities[1].value, 1000.0);
    EXPECT_EQ(inDataUnits(hu, {0.0f, 1.0f}), hu);   // already in data units: unchanged
}

// A version-1 TF and the same TF fixed in data units over the window bake the same table: existing
// sessions, presets and tests keep their images.
TEST(TransferFunctionLut, AWindowFractionTfAndItsDataUnitsBakeTheSameTable) {
    for (const std::string& name : builtinPresetNames())
        for (ValueRange window : {ValueRange{0.0f, 1.0f}, ValueRange{-1024.0f, 3071.0f}, ValueRange{3.5f, 250.25f}}) {
            const TransferFunction fractions = builtinPreset(name);
            if (!fractions.windowFractions) continue;
            const Lut a = bakeLut(fractions, window), b = bakeLut(inDataUnits(fractions, window), window);
            for (int i = 0; i < kLutSize; ++i)
                for (int c = 0; c < 4; ++c)
                    ASSERT_NEAR(a[size_t(i)][c], b[size_t(i)][c], 1e-6f) << name << " class " << i;
        }
}

// The window is a display range: a TF in HU keeps its meaning when it changes. A voxel of 350 HU is
// transparent and one of 800 HU opaque under any window that holds both; values past the TF's points
// read its end values.
TEST(TransferFunctionLut, ChangingTheWindowDoesNotMoveADataUnitTfOverTheData) {
    const TransferFunction tf = hounsfield();
    for (ValueRange window : {ValueRange{-1024.0f, 3071.0f}, ValueRange{-1000.0f, 1000.0f}, ValueRange{0.0f, 2000.0f}}) {
        const Lut lut = bakeLut(tf, window);
        const auto at = [&](float v) { return lut[classOf(v, window.lo, window.hi)]; };
        EXPECT_EQ(at(250.0f).a, 0.0f) << window.lo << ".." << window.hi;
        EXPECT_NEAR(at(900.0f).a, 0.8f, 1e-6f) << window.lo << ".." << window.hi;
        EXPECT_NEAR(at(1e6f).a, 0.8f, 1e-6f);        // past the last point and the window: the end value
        // Past the window, the TF at the window's edge (bakeLut's comment): the last colour stop's colour
        // where the window holds 1500 HU, the colour at 1000 HU where it ends there.
        const double edge = std::min(1800.0, double(window.hi));
        EXPECT_NEAR(at(1800.0f).r, evaluate(tf, edge).r, 1e-3) << window.lo << ".." << window.hi;
    }
    EXPECT_NEAR(bakeLut(tf, {-1024.0f, 3071.0f})[classOf(1800.0f, -1024.0f, 3071.0f)].r, 1.0f, 1e-6f);
    // The same TF in window fractions would move: 0.3 of the window is 205 HU in one, 600 HU in the other.
    const TransferFunction moving = fromSharedPoints("f", {{0.0, {1, 1, 1}, 0.0}, {0.3, {1, 1, 1}, 0.0}, {0.31, {1, 1, 1}, 1.0}});
    EXPECT_GT(bakeLut(moving, {-1024.0f, 3071.0f})[classOf(500.0f, -1024.0f, 3071.0f)].a, 0.5f);
    EXPECT_EQ(bakeLut(moving, {0.0f, 2000.0f})[classOf(500.0f, 0.0f, 2000.0f)].a, 0.0f);
}

TEST(TransferFunctionLut, ColourAndOpacityInterpolateEachOverItsOwnPoints) {
    TransferFunction tf;
    tf.colours = {{0.0, {1, 0, 0}}, {100.0, {0, 0, 1}}};
    tf.opacities = {{0.0, 0.0}, {20.0, 0.0}, {30.0, 1.0}, {40.0, 0.0}};
    const glm::dvec4 at25 = evaluate(tf, 25.0);
    EXPECT_NEAR(at25.r, 0.75, 1e-12);
    EXPECT_NEAR(at25.b, 0.25, 1e-12);
    EXPECT_NEAR(at25.a, 0.5, 1e-12);
    EXPECT_EQ(evaluate(tf, 50.0).a, 0.0);
    EXPECT_NEAR(evaluate(tf, 50.0).b, 0.5, 1e-12);
}

TEST(TransferFunctionEdit, ShiftMovesEveryPointByTheOffsetAndNothingElse) {
    const TransferFunction tf = hounsfield();
    const TransferFunction moved = shifted(tf, 125.5);
    ASSERT_EQ(moved.colours.size(), tf.colours.size());
    ASSERT_EQ(moved.opacities.size(), tf.opacities.size());
    for (size_t i = 0; i < tf.colours.size(); ++i) {
        EXPECT_EQ(moved.colours[i].value, tf.colours[i].value + 125.5);
        EXPECT_EQ(moved.colours[i].colour, tf.colours[i].colour);
    }
    for (size_t i = 0; i < tf.opacities.size(); ++i) {
        EXPECT_EQ(moved.opacities[i].value, tf.opacities[i].value + 125.5);
        EXPECT_EQ(moved.opacities[i].opacity, tf.opacities[i].opacity);
    }
    // What was at x is now at x + offset.
    for (double x : {-700.0, -400.0, 0.0, 500.0, 650.0})
        EXPECT_NEAR(glm::length(evaluate(moved, x + 125.5) - evaluate(tf, x)), 0.0, 1e-12) << x;
    EXPECT_EQ(shifted(tf, 0.0), tf);
}

TEST(TransferFunctionEdit, RescaleMapsTheExtentOntoTheRangeAndKeepsProportions) {
    const TransferFunction tf = hounsfield();   // extent -1000 .. 1500
    EXPECT_EQ(extentOf(tf).lo, -1000.0);
    EXPECT_EQ(extentOf(tf).hi, 1500.0);
    const TransferFunction r = rescaled(tf, 0.0, 255.0);
    EXPECT_EQ(extentOf(r).lo, 0.0);
    EXPECT_EQ(extentOf(r).hi, 255.0);
    // -400 HU is 0.24 of the way: 61.2 of 255.
    EXPECT_NEAR(r.opacities[2].value, 0.24 * 255.0, 1e-9);
    EXPECT_EQ(r.opacities[2].opacity, tf.opacities[2].opacity);
    for (double t : {0.1, 0.37, 0.5, 0.9})
        EXPECT_NEAR(glm::length(evaluate(r, 255.0 * t) - evaluate(tf, -1000.0 + 2500.0 * t)), 0.0, 1e-9) << t;
    // Back again: the original, to rounding.
    const TransferFunction back = rescaled(r, -1000.0, 1500.0);
    for (size_t i = 0; i < tf.opacities.size(); ++i) EXPECT_NEAR(back.opacities[i].value, tf.opacities[i].value, 1e-9);
    // All points at one value: moved to the middle of the range.
    TransferFunction point;
    point.colours = {{5.0, {1, 1, 1}}};
    point.opacities = {{5.0, 0.5}};
    EXPECT_EQ(rescaled(point, 100.0, 200.0).opacities[0].value, 150.0);
    EXPECT_THROW(rescaled(tf, 10.0, 10.0), RenderError);
    EXPECT_THROW(rescaled(tf, 0.0, INFINITY), RenderError);
}

TEST(TransferFunctionFile, BadFieldsAreRefusedNamingTheFileAndTheField) {
    const std::string colours = R"("colour": [{"value": 0, "rgb": [0, 0, 0]}, {"value": 10, "rgb": [1, 1, 1]}])";
    const std::string opacities = R"("opacity": [{"value": 0, "opacity": 0}, {"value": 10, "opacity": 1}])";
    const std::pair<std::string, std::string> bad[] = {
        {"{", "not valid JSON"},
        {"7", "expected a JSON object"},
        {"[]", "an empty preset list"},   // a list is a ParaView preset list
        {R"({"version": 2, )" + colours + "}", "field 'opacity': missing"},
        {R"({"version": 2, )" + opacities + "}", "field 'colour': missing"},
        {R"({"version": 2, "colour": [], )" + opacities + "}", "field 'colour': has no control points"},
        {R"({"version": 2, "colour": {}, )" + opacities + "}", "field 'colour': missing, expected an array"},
        {R"({"version": 2, "colour": [{"value": 0, "rgb": [1, 1]}], )" + opacities + "}",
         "field 'colour[0].rgb'"},
        {R"({"version": 2, "colour": [{"value": 0, "rgb": [1, 2, 1]}], )" + opacities + "}",
         "field 'colour[0].rgb': a value is 2.000000, expected [0,1]"},
        {R"({"version": 2, "colour": [{"value": "low", "rgb": [1, 1, 1]}], )" + opacities + "}",
         "field 'colour[0].value': \"low\", expected a number"},
        {R"({"version": 2, "colour": [{"rgb": [1, 1, 1]}], )" + opacities + "}", "field 'colour[0].value': missing"},
        {R"({"version": 2, )" + colours + R"(, "opacity": [{"value": 0, "opacity": 0}, {"value": 1, "opacity": 1.5}]})",
         "field 'opacity[1].opacity': 1.500000, expected [0,1]"},
        {R"({"version": 2, )" + colours + R"(, "opacity": [{"value": 0}]})", "field 'opacity[0].opacity': missing"},
        {R"({"version": 2, )" + colours + R"(, "opacity": [7]})", "field 'opacity[0].value': missing"},
        {R"({"version": 2, "units": "HU", )" + colours + ", " + opacities + "}", "field 'units': \"HU\", expected"},
        {R"({"version": 2, "units": "window fraction", )" + colours + ", " + opacities + "}",
         "field 'colour[1].value': 10.000000, expected [0,1]"},
        {R"({"version": 2, "name": 3, )" + colours + ", " + opacities + "}", "field 'name': 3, expected a string"},
        {R"({"version": 3, )" + colours + ", " + opacities + "}", "field 'version': 3 is newer than this SplatLab reads (2)"},
        {R"({"version": "1", "points": []})", "field 'version': \"1\", expected a whole number >= 1"},
        {R"({"version": 1, "name": "x"})", "field 'points': missing"},
        {R"({"points": []})", "field 'points': has no control points"},
        {R"({"points": [{"value": 1.5, "colour": [1, 1, 1], "opacity": 1}]})",
         "field 'points[0].value': 1.500000, expected [0,1]"},
        {R"({"points": [{"value": 0.5, "colour": [1, 1], "opacity": 1}]})", "field 'points[0].colour'"},
        {R"({"points": [{"value": 0.5, "colour": [1, 1, 1]}]})", "field 'points[0].opacity': missing"},
    };
    for (const auto& [text, expect] : bad) {
        const auto path = write("bad_tf.json", text);
        try {
            loadTransferFunction(path);
            ADD_FAILURE() << "accepted: " << text;
        } catch (const LoadError& e) {
            EXPECT_THAT(e.what(), HasSubstr("bad_tf.json")) << text;
            EXPECT_THAT(e.what(), HasSubstr(expect)) << text;
        }
    }
    EXPECT_THROW(transferFunctionFromSpec("no-such-preset"), RenderError);
}

TEST(SplatScene, TheVisibleRangeSpansTheValuesOfTheVoxelsDrawn) {
    Volume v = makeSphereShells(12, 4.0, 1.5);
    const ValueRange window = v.range;
    TransferFunction tf;
    const double mid = 0.5 * (double(window.lo) + window.hi);
    tf.colours = {{window.lo, {1, 1, 1}}};
    tf.opacities = {{window.lo, 0.0}, {mid, 0.0}, {mid + 1e-9, 1.0}};
    const SplatScene s = buildSplatScene(v, tf, window);
    const ValueRange visible = visibleValueRange(s);
    const double classWidth = (double(window.hi) - window.lo) / kLutSize;
    EXPECT_GE(visible.lo, mid - classWidth);
    EXPECT_NEAR(visible.hi, window.hi, 1e-3);
    size_t drawn = 0;
    for (size_t i = 0; i < v.values.size(); ++i)
        if (s.lut[s.classes[i]].a > 0.0f) {
            ++drawn;
            EXPECT_GE(v.values[i], visible.lo - 1e-4f);
            EXPECT_LE(v.values[i], visible.hi + 1e-4f);
        }
    EXPECT_GT(drawn, 0u);
    TransferFunction none = tf;
    none.opacities = {{0.0, 0.0}};
    SplatScene hidden = s;
    setTransferFunction(hidden, none);
    EXPECT_EQ(visibleValueRange(hidden).hi, 0.0f);
}
