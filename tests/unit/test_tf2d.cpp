// The 2D transfer function (value x gradient magnitude widgets): the widgets' weights, how they combine,
// the file format, the scene's table and culling, Shift and Rescale, and the ground truth.
#include "renderer/errors.h"
#include "renderer/math/metrics.h"
#include "renderer/model/gradients.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/reference_renderer.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

using namespace renderer;

namespace {

Widget2D rectangle(double lo, double hi, double gLo, double gHi, glm::dvec3 colour = glm::dvec3(1.0),
                   double opacity = 1.0) {
    Widget2D w;
    w.shape = WidgetShape::Rectangle;
    w.valueLo = lo, w.valueHi = hi, w.magnitudeLo = gLo, w.magnitudeHi = gHi;
    w.colour = colour, w.opacity = opacity;
    return w;
}

Widget2D triangle(double apex, double halfWidth, double top, glm::dvec3 colour = glm::dvec3(1.0),
                  double opacity = 1.0) {
    Widget2D w;
    w.shape = WidgetShape::Triangle;
    w.apex = apex, w.halfWidth = halfWidth, w.magnitudeTop = top;
    w.colour = colour, w.opacity = opacity;
    return w;
}

// A TF in data units with the given widgets and a visible 1D ramp (which the widgets override).
TransferFunction withWidgets(std::vector<Widget2D> widgets) {
    TransferFunction tf;
    tf.name = "tf2d";
    tf.colours = {{0.0, {0.1, 0.2, 0.3}}, {1.0, {0.9, 0.8, 0.7}}};
    tf.opacities = {{0.0, 0.5}, {1.0, 0.5}};
    tf.widgets2d = std::move(widgets);
    return tf;
}

TransferFunction fromText(const std::string& text) {
    return transferFunctionFromJson(nlohmann::json::parse(text), "t.json", "t");
}

std::string loadError(const std::string& text) {
    try {
        fromText(text);
    } catch (const LoadError& e) {
        return e.what();
    }
    return "(loaded)";
}

} // namespace

TEST(Tf2d, RectangleIsOneInsideAndOnItsEdgesAndZeroOutside) {
    const Widget2D r = rectangle(10.0, 20.0, 1.0, 3.0);
    EXPECT_EQ(widgetWeight(r, 15.0, 2.0), 1.0);
    EXPECT_EQ(widgetWeight(r, 10.0, 1.0), 1.0);   // corners and edges belong to it
    EXPECT_EQ(widgetWeight(r, 20.0, 3.0), 1.0);
    EXPECT_EQ(widgetWeight(r, 9.999, 2.0), 0.0);
    EXPECT_EQ(widgetWeight(r, 20.001, 2.0), 0.0);
    EXPECT_EQ(widgetWeight(r, 15.0, 0.999), 0.0);
    EXPECT_EQ(widgetWeight(r, 15.0, 3.001), 0.0);
}

TEST(Tf2d, TriangleIsOneOnItsCentreLineFallingToZeroAtItsSidesAndNothingAboveItsTop) {
    const Widget2D t = triangle(100.0, 40.0, 8.0);
    EXPECT_EQ(widgetWeight(t, 100.0, 8.0), 1.0);   // centre line, at the top
    EXPECT_EQ(widgetWeight(t, 100.0, 2.0), 1.0);   // centre line, lower down
    EXPECT_EQ(widgetWeight(t, 100.0, 0.0), 1.0);   // the apex
    EXPECT_EQ(widgetWeight(t, 100.5, 0.0), 0.0);   // beside the apex: no width there
    // At magnitude 4 the half-width is 20: halfway out 0.5, at the side 0, beyond it 0.
    EXPECT_NEAR(widgetWeight(t, 110.0, 4.0), 0.5, 1e-12);
    EXPECT_NEAR(widgetWeight(t, 90.0, 4.0), 0.5, 1e-12);
    EXPECT_EQ(widgetWeight(t, 120.0, 4.0), 0.0);
    EXPECT_EQ(widgetWeight(t, 125.0, 4.0), 0.0);
    EXPECT_NEAR(widgetWeight(t, 130.0, 8.0), 0.25, 1e-12);   // at the top: half-width 40
    EXPECT_EQ(widgetWeight(t, 100.0, 8.01), 0.0);            // above the top
    EXPECT_EQ(widgetWeight(t, 100.0, -1.0), 0.0);
}

TEST(Tf2d, OpacityIsTheLargestWidgetsAndColourTheirWeightedMean) {
    TransferFunction tf = withWidgets({rectangle(0.0, 10.0, 0.0, 5.0, {1.0, 0.0, 0.0}, 0.6),
                                       rectangle(5.0, 15.0, 0.0, 5.0, {0.0, 0.0, 1.0}, 0.2)});
    EXPECT_EQ(evaluate2d(tf, 2.0, 1.0), glm::dvec4(1.0, 0.0, 0.0, 0.6));
    const glm::dvec4 both = evaluate2d(tf, 7.0, 1.0);
    EXPECT_NEAR(both.a, 0.6, 1e-12);   // the largest, not the sum
    EXPECT_NEAR(both.r, 0.75, 1e-12);  // 0.6 / (0.6 + 0.2) of red
    EXPECT_NEAR(both.b, 0.25, 1e-12);
    EXPECT_EQ(evaluate2d(tf, 20.0, 1.0), glm::dvec4(0.0));   // no widget there: transparent
}

TEST(Tf2d, RoundTripsThroughTheFileAndOldFilesReadWithout) {
    TransferFunction tf = withWidgets({rectangle(-100.5, 300.25, 0.5, 1e9, {0.2, 0.4, 0.6}, 0.7),
                                       triangle(400.0, 150.0, 120.0, {1.0, 0.9, 0.8}, 0.35)});
    const TransferFunction back = transferFunctionFromJson(toJson(tf), "x.json", "x");
    EXPECT_EQ(back, tf);
    EXPECT_EQ(toJson(tf)["widgets2d"][1]["shape"], "triangle");
    // A TF without widgets writes no widgets2d, and such a file reads with none.
    tf.widgets2d.clear();
    EXPECT_FALSE(toJson(tf).contains("widgets2d"));
    EXPECT_TRUE(transferFunctionFromJson(toJson(tf), "x.json", "x").widgets2d.empty());
    EXPECT_TRUE(fromText(R"({"version": 2, "colour": [{"value": 0, "rgb": [1, 1, 1]}],
                             "opacity": [{"value": 0, "opacity": 1}], "widgets2d": []})")
                    .widgets2d.empty());
}

TEST(Tf2d, BadWidgetsAreRefusedNamingTheFieldAndTheExpectation) {
    const std::string head = R"({"version": 2, "colour": [{"value": 0, "rgb": [1, 1, 1]}],
                                 "opacity": [{"value": 0, "opacity": 1}], "widgets2d": )";
    const auto refused = [&](const std::string& widgets, const std::string& field, const std::string& why) {
        const std::string e = loadError(head + widgets + "}");
        EXPECT_NE(e.find("t.json"), std::string::npos) << e;
        EXPECT_NE(e.find(field), std::string::npos) << e;
        EXPECT_NE(e.find(why), std::string::npos) << e;
    };
    refused(R"({"shape": "rectangle"})", "widgets2d", "expected an array");
    refused(R"([{"rgb": [1, 1, 1], "opacity": 1}])", "widgets2d[0].shape", "expected \"rectangle\" or \"triangle\"");
    refused(R"([{"shape": "circle"}])", "widgets2d[0].shape", "expected \"rectangle\" or \"triangle\"");
    refused(R"([{"shape": "rectangle", "value": [5, 1], "magnitude": [0, 1], "rgb": [1, 1, 1], "opacity": 1}])",
            "widgets2d[0].value", "low <= high");
    refused(R"([{"shape": "rectangle", "value": [0, 1], "magnitude": [-1, 1], "rgb": [1, 1, 1], "opacity": 1}])",
            "widgets2d[0].magnitude", "0 <= low <= high");
    refused(R"([{"shape": "rectangle", "value": [0, 1], "rgb": [1, 1, 1], "opacity": 1}])",
            "widgets2d[0].magnitude", "missing");
    refused(R"([{"shape": "triangle", "apex": 3, "halfWidth": 0, "magnitudeTop": 2, "rgb": [1, 1, 1], "opacity": 1}])",
            "widgets2d[0].halfWidth", "expected a width > 0");
    refused(R"([{"shape": "triangle", "apex": 3, "halfWidth": 1, "magnitudeTop": -2, "rgb": [1, 1, 1], "opacity": 1}])",
            "widgets2d[0].magnitudeTop", "expected a magnitude > 0");
    refused(R"([{"shape": "triangle", "apex": 3, "halfWidth": 1, "magnitudeTop": 2, "rgb": [1, 1, 1], "opacity": 2}])",
            "widgets2d[0].opacity", "expected [0,1]");
    const std::string v1 = loadError(R"({"points": [{"value": 0, "colour": [1, 1, 1], "opacity": 1}],
        "widgets2d": [{"shape": "triangle", "apex": 3, "halfWidth": 1, "magnitudeTop": 2, "rgb": [1, 1, 1], "opacity": 1}]})");
    EXPECT_NE(v1.find("widgets2d"), std::string::npos) << v1;
    EXPECT_NE(v1.find("version 2"), std::string::npos) << v1;
}

TEST(Tf2d, ShiftAndRescaleMoveTheWidgetsValues) {
    TransferFunction tf = withWidgets({rectangle(0.2, 0.4, 1.0, 2.0), triangle(0.5, 0.25, 3.0)});
    const TransferFunction moved = shifted(tf, 10.0);
    EXPECT_EQ(moved.widgets2d[0].valueLo, 10.2);
    EXPECT_EQ(moved.widgets2d[0].magnitudeHi, 2.0);   // magnitudes stay
    EXPECT_EQ(moved.widgets2d[1].apex, 10.5);
    // Extent 0 .. 1 (the points; the triangle reaches 0.25 .. 0.75) onto 0 .. 100.
    const TransferFunction scaled = rescaled(tf, 0.0, 100.0);
    EXPECT_NEAR(scaled.widgets2d[0].valueLo, 20.0, 1e-9);
    EXPECT_NEAR(scaled.widgets2d[0].valueHi, 40.0, 1e-9);
    EXPECT_NEAR(scaled.widgets2d[1].apex, 50.0, 1e-9);
    EXPECT_NEAR(scaled.widgets2d[1].halfWidth, 25.0, 1e-9);
    EXPECT_EQ(scaled.widgets2d[1].magnitudeTop, 3.0);
    // A TF of widgets only has their extent.
    tf.colours.clear(), tf.opacities.clear();
    EXPECT_EQ(extentOf(tf).lo, 0.2);
    EXPECT_EQ(extentOf(tf).hi, 0.75);
}

TEST(Tf2d, WaitsForTheGradientsThenDecidesColourOpacityAndCulling) {
    const Volume volume = makeMarschnerLobb(16);
    const GradientField field = *computeGradients(volume);
    const double mean = gradientMagnitudeStats(field).mean;
    const double lo = volume.range.lo, span = double(volume.range.hi) - volume.range.lo;
    // Strong gradients of the upper half of the values, in orange.
    const TransferFunction tf =
        withWidgets({rectangle(lo + 0.5 * span, lo + span, mean, 1e9, {1.0, 0.5, 0.0}, 0.8)});
    SplatScene scene = buildSplatScene(volume, tf);
    EXPECT_TRUE(scene.tf2d.empty()) << "no gradients yet: the 1D curves";
    EXPECT_EQ(scene.visibleCount(), volume.voxelCount());
    addGradients(scene, field);
    ASSERT_EQ(scene.tf2d.size(), size_t(kTf2dCells));
    size_t visible = 0;
    for (uint32_t v = 0; v < uint32_t(volume.voxelCount()); ++v) {
        const float a = scene.opacityOf(v);
        const glm::dvec4 want =
            evaluate2d(tf, lo + (((scene.classes[v] >> kTf2dClassShift) + 0.5) / kTf2dValueBins) * span,
                       field.magnitude(v));
        // The cell's magnitude is the middle of 4 bytes: a voxel near the edge may fall on either side.
        if (std::abs(field.magnitude(v) - mean) > 0.25 * mean) {
            EXPECT_EQ(a, float(want.a)) << v;
        }
        if (a > 0.0f) {
            ++visible;
            EXPECT_EQ(scene.colourOf(v), glm::dvec3(glm::vec3(1.0f, 0.5f, 0.0f)));
            EXPECT_GT(scene.lut[scene.classes[v]].a, 0.0f) << "a class with a visible voxel is drawn";
        }
    }
    EXPECT_EQ(scene.visibleCount(), visible);
    EXPECT_GT(visible, 100u);
    EXPECT_LT(visible, volume.voxelCount() / 2);
    EXPECT_EQ(scene.lut[0].a, 0.0f) << "the lowest values' class is culled by bucket";
    // The histogram the editor draws counts every voxel once.
    const std::vector<uint32_t> histogram = valueGradientHistogram(scene);
    ASSERT_EQ(histogram.size(), size_t(kTf2dCells));
    size_t total = 0;
    for (uint32_t c : histogram) total += c;
    EXPECT_EQ(total, volume.voxelCount());
    // Removing the widgets brings the curves back.
    TransferFunction none = tf;
    none.widgets2d.clear();
    setTransferFunction(scene, none);
    EXPECT_TRUE(scene.tf2d.empty());
    EXPECT_EQ(scene.visibleCount(), volume.voxelCount());
}

// A rectangle taking one value range at every gradient is the 1D TF with that range: the same truth
// (and the same splats), its edges on the table's value bins so both classify each voxel alike.
TEST(Tf2d, ARectangleOverAllGradientsGivesTheTruthOfTheEquivalent1dTf) {
    const Volume volume = makeMarschnerLobb(16);
    const GradientField field = *computeGradients(volume);
    const double lo = volume.range.lo, span = double(volume.range.hi) - volume.range.lo;
    const double a = lo + span * 96.0 / kTf2dValueBins, b = lo + span * 200.0 / kTf2dValueBins;
    const double d = span * 1e-6;   // well inside a class (1 / 4096 of the span)
    const glm::dvec3 colour(0.9, 0.6, 0.3);
    TransferFunction oneD;
    oneD.colours = {{lo, colour}, {lo + span, colour}};
    oneD.opacities = {{a - d, 0.0}, {a, 0.7}, {b, 0.7}, {b + d, 0.0}};
    TransferFunction twoD = oneD;
    twoD.colours = {{lo, {0.0, 0.0, 1.0}}};   // the curves, overridden by the widget
    twoD.opacities = {{lo, 0.3}};
    twoD.widgets2d = {rectangle(a, b, 0.0, 1e12, colour, 0.7)};
    SplatScene scene1 = buildSplatScene(volume, oneD), scene2 = buildSplatScene(volume, twoD);
    addGradients(scene1, field);
    addGradients(scene2, field);
    ASSERT_FALSE(scene2.tf2d.empty());
    EXPECT_EQ(scene2.visibleCount(), scene1.visibleCount());
    EXPECT_GT(scene1.visibleCount(), 200u);
    EXPECT_LT(scene1.visibleCount(), volume.voxelCount() - 200u);
    const ImagePlane plane = makeImagePlane(Camera{30, 20, 2.5, 30.0}, scene1.centre, scene1.radius, 24, 24);
    const SplatSettings s;
    const GroundTruthOptions options{.tolerance = 1e-4};
    EXPECT_NE(groundTruthKey(scene1, plane, s, options), groundTruthKey(scene2, plane, s, options));
    const Image truth1 = renderGroundTruth(scene1, plane, s, options), truth2 = renderGroundTruth(scene2, plane, s, options);
    EXPECT_LT(compareImages(truth2, truth1).maxAbs, 1e-6);
    EXPECT_GT(compareImages(truth1, Image(24, 24)).maxAbs, 0.05) << "the range must show";
    EXPECT_LT(compareImages(renderReference(scene2, plane, s), renderReference(scene1, plane, s)).maxAbs, 1e-6);
}
