// ParaView colour-map presets: small ones written here in ParaView's published JSON (a list of presets
// with "RGBPoints" [x, r, g, b, ...] and "Points" [x, opacity, midpoint, sharpness, ...]) import as the
// same TF typed by hand, ours export to it and back, and what a TF cannot hold exactly is refused.
#include "renderer/errors.h"
#include "renderer/model/paraview_preset.h"
#include "test_paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>

using namespace renderer;
using testing::HasSubstr;

namespace {

std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto path = testing_support::testOutputDir("paraview") / name;
    std::ofstream(path) << text;
    return path;
}

} // namespace

TEST(ParaViewPreset, ImportsAsTheSameTfTypedByHandAndBakesTheSameTable) {
    const auto path = write("bone.json", R"([
  {
    "Name": "CT-Bone-ish",
    "ColorSpace": "RGB",
    "NanColor": [1, 0, 0],
    "RGBPoints": [-1000, 0, 0, 0,  200, 0.9, 0.6, 0.5,  1500, 1, 1, 1],
    "Points": [-1000, 0, 0.5, 0,  150, 0, 0.5, 0,  700, 0.8, 0.5, 0]
  }
])");
    TransferFunction byHand;
    byHand.name = "CT-Bone-ish";
    byHand.colours = {{-1000, {0, 0, 0}}, {200, {0.9, 0.6, 0.5}}, {1500, {1, 1, 1}}};
    byHand.opacities = {{-1000, 0.0}, {150, 0.0}, {700, 0.8}};
    const TransferFunction imported = loadTransferFunction(path);   // the TF loader takes ParaView's JSON too
    EXPECT_EQ(imported, byHand);
    EXPECT_EQ(loadParaViewPreset(path), byHand);
    const ValueRange window{-1024.0f, 3071.0f};
    EXPECT_EQ(bakeLut(imported, window), bakeLut(byHand, window));
}

TEST(ParaViewPreset, OursExportAndImportBack) {
    TransferFunction tf;
    tf.name = "mine";
    tf.colours = {{0, {0, 0, 0}}, {550, {0.9, 0.62, 0.5}}, {3926, {1, 1, 1}}};
    tf.opacities = {{0, 0.0}, {620, 0.06}, {850, 0.0}, {2600, 0.8}};
    const auto path = testing_support::testOutputDir("paraview") / "mine.json";
    saveParaViewPreset(tf, path);
    EXPECT_EQ(loadParaViewPreset(path), tf);
    const nlohmann::json j = toParaView(tf);
    ASSERT_TRUE(j.is_array());
    EXPECT_EQ(j[0]["ColorSpace"], "RGB");
    EXPECT_EQ(j[0]["RGBPoints"].size(), 12u);
    EXPECT_EQ(j[0]["Points"].size(), 16u);
    EXPECT_EQ(j[0]["Points"][6], 0.5);   // the second point's midpoint: linear
}

TEST(ParaViewPreset, WithoutPointsOpacityRampsOverTheColourStops) {
    const TransferFunction tf =
        loadParaViewPreset(write("ramp.json", R"({"Name": "grey", "RGBPoints": [10, 0, 0, 0, 20, 1, 1, 1]})"));
    ASSERT_EQ(tf.opacities.size(), 2u);
    EXPECT_EQ(tf.opacities[0], (OpacityPoint{10, 0.0}));
    EXPECT_EQ(tf.opacities[1], (OpacityPoint{20, 1.0}));
}

TEST(ParaViewPreset, WhatATfCannotHoldExactlyIsRefusedNamingTheField) {
    const std::pair<std::string, std::string> bad[] = {
        {R"([])", "an empty preset list"},
        {R"([{"ColorSpace": "Diverging", "RGBPoints": [0, 0, 0, 1, 1, 1, 0, 0]}])", "field 'ColorSpace': \"Diverging\""},
        {R"([{"RGBPoints": [0, 0, 0, 1, 1, 1, 0]}])", "field 'RGBPoints': expected a non-empty array"},
        {R"([{"Name": "x"}])", "field 'RGBPoints': missing"},
        {R"([{"RGBPoints": [0, 1.5, 0, 0]}])", "field 'RGBPoints[1]': 1.500000, expected [0,1]"},
        {R"([{"RGBPoints": [0, "red", 0, 0]}])", "field 'RGBPoints[1]': \"red\", expected a finite number"},
        {R"([{"RGBPoints": [0, 0, 0, 0], "Points": [0, 0.2, 0.3, 0]}])", "field 'Points[2]': midpoint 0.300000"},
        {R"([{"RGBPoints": [0, 0, 0, 0], "Points": [0, 2, 0.5, 0]}])", "field 'Points[1]': 2.000000, expected [0,1]"},
        {R"([3])", "expected a ParaView preset"},
    };
    for (const auto& [text, expect] : bad) {
        const auto path = write("bad_preset.json", text);
        try {
            loadParaViewPreset(path);
            ADD_FAILURE() << "accepted: " << text;
        } catch (const LoadError& e) {
            EXPECT_THAT(e.what(), HasSubstr("bad_preset.json")) << text;
            EXPECT_THAT(e.what(), HasSubstr(expect)) << text;
        }
    }
}
