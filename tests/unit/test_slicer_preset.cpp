// 3D Slicer's volume-rendering presets: a small presets.xml written here in Slicer's published format
// (<VolumeProperty name= scalarOpacity="N x o ..." colorTransfer="N x r g b ..." gradientOpacity=.../>)
// imports as the same TF typed by hand, a preset is picked by name, and bad or damaged files are refused
// naming the file, the preset and the attribute, never crashing.
#include "renderer/errors.h"
#include "renderer/model/slicer_preset.h"
#include "test_paths.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

using namespace renderer;
using testing::HasSubstr;

namespace {

// Two presets as Slicer writes them: CT-Bone's numbers, and a second with a gradient opacity that is not
// all 1 (CT-Bones's numbers, with its gradient opacity changed to fall off).
const std::string kPresets = R"(<?xml version="1.0" encoding="utf-8"?>
<MRML>
  <!-- <VolumeProperty name="Commented" scalarOpacity="2 0 1" colorTransfer="4 0 1 1 1"/> -->
  <VolumeProperty selected="false" hideFromEditors="false" name="CT-Bone" gradientOpacity="4 0 1 255 1"
    userTags="" specularPower="10" scalarOpacity="8 -3024 0 -16.4458 0 641.385 0.715686 3071 0.705882"
    id="vtkMRMLVolumePropertyNode3" specular="0.2" shade="1" ambient="0.1"
    colorTransfer="16 -3024 0 0 0 -16.4458 0.729412 0.254902 0.301961 641.385 0.905882 0.815686 0.552941 3071 1 1 1"
    selectable="true" diffuse="0.9" interpolation="1"/>
  <VolumeProperty name="Bones &amp; edges" gradientOpacity="4 0 0.2 985.12 1" specularPower="1"
    scalarOpacity="8 -1000 0 152.19 0 278.93 0.190476 952 0.2" id="vtkMRMLVolumePropertyNode4"
    colorTransfer="20 -1000 0.3 0.3 1 -488 0.3 1 0.3 463.28 1 0 0 659.15 1 0.912535 0.0374849 953 1 0.3 0.3"
    interpolation="1"></VolumeProperty>
</MRML>
)";

std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto path = testing_support::testOutputDir("slicer") / name;
    EXPECT_TRUE(testing_support::writeFile(path, text));
    return path;
}

TransferFunction ctBoneByHand() {
    TransferFunction tf;
    tf.name = "CT-Bone";
    tf.opacities = {{-3024, 0.0}, {-16.4458, 0.0}, {641.385, 0.715686}, {3071, 0.705882}};
    tf.colours = {{-3024, {0, 0, 0}},
                  {-16.4458, {0.729412, 0.254902, 0.301961}},
                  {641.385, {0.905882, 0.815686, 0.552941}},
                  {3071, {1, 1, 1}}};
    return tf;
}

} // namespace

TEST(SlicerPreset, ImportsAsTheSameTfTypedByHandAndBakesTheSameTable) {
    const auto path = write("presets.xml", kPresets);
    const std::vector<SlicerPreset> presets = loadSlicerPresets(path);
    ASSERT_EQ(presets.size(), 2u) << "the commented-out preset was read, or one was missed";
    EXPECT_EQ(presets[0].tf, ctBoneByHand());
    EXPECT_EQ(presets[1].tf.name, "Bones & edges");
    EXPECT_EQ(presets[1].tf.colours.size(), 5u);
    const ValueRange window{-1024.0f, 3071.0f};
    const Lut imported = bakeLut(presets[0].tf, window), byHand = bakeLut(ctBoneByHand(), window);
    ASSERT_EQ(imported.size(), byHand.size());
    for (size_t i = 0; i < imported.size(); ++i)
        for (int c = 0; c < 4; ++c)
            ASSERT_NEAR(imported[i][c], byHand[i][c], 1e-6) << "entry " << i << " channel " << c;
    // The bone's opacity is in the table: not an empty TF that matches an empty TF.
    EXPECT_NEAR(evaluate(presets[0].tf, 641.385).a, 0.715686, 1e-12);
}

TEST(SlicerPreset, ASpecPicksAPresetByNameAndNotesWhatIsLeftOut) {
    const auto path = write("presets.xml", kPresets);
    std::vector<std::string> notes;
    EXPECT_EQ(transferFunctionFromSpec(path.string() + "#CT-Bone", &notes), ctBoneByHand());
    EXPECT_TRUE(notes.empty()) << "CT-Bone's gradient opacity is all 1: " << notes.front();

    // The second preset's gradient opacity falls to 0.2: the TF's gradient opacity, nothing to note.
    const LoadedSlicerPreset second = loadSlicerPreset({path, "Bones & edges"});
    EXPECT_EQ(second.preset.tf.gradientOpacity, (std::vector<GradientOpacityPoint>{{0.0, 0.2}, {985.12, 1.0}}));
    EXPECT_TRUE(second.notes.empty()) << second.notes.front();

    // No name: the first, with a note that there are more.
    notes.clear();
    EXPECT_EQ(transferFunctionFromSpec(path.string(), &notes), ctBoneByHand());
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_THAT(notes[0], HasSubstr("holds 2 presets; took the first, CT-Bone"));

    try {
        transferFunctionFromSpec(path.string() + "#CT-Lung");
        ADD_FAILURE() << "an unknown preset name was accepted";
    } catch (const LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr("no preset named 'CT-Lung' (it holds: CT-Bone, Bones & edges)"));
    }
    EXPECT_FALSE(slicerPresetSpec("ct-bone").has_value());
    EXPECT_FALSE(slicerPresetSpec("bone.json").has_value());
    ASSERT_TRUE(slicerPresetSpec("a/presets.XML#x#y").has_value());
    EXPECT_EQ(slicerPresetSpec("a/presets.XML#x#y")->file, "a/presets.XML");
    EXPECT_EQ(slicerPresetSpec("a/presets.XML#x#y")->name, "x#y");
}

TEST(SlicerPreset, BadInputIsRefusedNamingTheFilePresetAndAttribute) {
    const auto one = [](const std::string& attributes) {
        return "<MRML><VolumeProperty " + attributes + "/></MRML>";
    };
    const std::string colour = R"(colorTransfer="8 0 0 0 0 100 1 1 1")";
    const std::string opacity = R"(scalarOpacity="4 0 0 100 1")";
    const std::pair<std::string, std::string> bad[] = {
        {"<MRML></MRML>", "no <VolumeProperty> element"},
        {one(opacity + " " + colour), "field 'VolumeProperty 1.name': missing"},
        {one(R"(name="A" )" + colour), "field 'A.scalarOpacity': missing"},
        {one(R"(name="A" )" + opacity), "field 'A.colorTransfer': missing"},
        {one(R"(name="A" scalarOpacity="6 0 0 100 1" )" + colour),
         "field 'A.scalarOpacity': count 6 but 4 numbers follow it; expected a count N, then N numbers in "
         "groups of 2"},
        {one(R"(name="A" scalarOpacity="3 0 0 100" )" + colour), "field 'A.scalarOpacity': count 3.000000"},
        {one(R"(name="A" scalarOpacity="4 0 zero 100 1" )" + colour),
         "field 'A.scalarOpacity': 'zero' (number 3), expected a finite number"},
        {one(R"(name="A" scalarOpacity="4 0 nan 100 1" )" + colour),
         "'nan' (number 3), expected a finite number"},
        {one(R"(name="A" scalarOpacity="4 100 0 0 1" )" + colour),
         "field 'A.scalarOpacity': position 0.000000 after 100.000000, expected positions in increasing "
         "order"},
        {one(R"(name="A" colorTransfer="8 0 0 0 0 100 1 2 1" )" + opacity),
         "field 'A.colorTransfer': 2.000000 at position 100.000000, expected [0,1]"},
        {one(R"(name="A" gradientOpacity="2 0" )" + opacity + " " + colour),
         "field 'A.gradientOpacity': count 2 but 1"},
        {"<VolumeProperty name=\"A\" scalarOpacity=\"4 0 0",
         "field 'VolumeProperty 1.scalarOpacity': the quoted value never ends"},
        {"<VolumeProperty name=\"A\"", "field 'VolumeProperty 1': the element never ends"},
        {"<VolumeProperty name=A/>", "field 'VolumeProperty 1.name': expected a quoted value"},
    };
    for (const auto& [text, expect] : bad) {
        const auto path = write("bad_presets.xml", text);
        try {
            loadSlicerPresets(path);
            ADD_FAILURE() << "accepted: " << text;
        } catch (const LoadError& e) {
            EXPECT_THAT(e.what(), HasSubstr("bad_presets.xml")) << text;
            EXPECT_THAT(e.what(), HasSubstr(expect)) << text;
        }
    }
}

// Every truncation of a good file, and random byte changes, either import or throw LoadError: no other
// exception, no crash (ASan builds check the reads).
TEST(SlicerPreset, TruncatedAndMutatedFilesNeverCrash) {
    size_t accepted = 0, refused = 0;
    const auto tryParse = [&](const std::string& text) {
        try {
            const std::vector<SlicerPreset> presets = slicerPresetsFromXml(text, "fuzzed.xml");
            EXPECT_FALSE(presets.empty());
            ++accepted;
        } catch (const LoadError&) {
            ++refused;
        }
    };
    for (size_t n = 0; n <= kPresets.size(); ++n)
        tryParse(kPresets.substr(0, n));
    std::mt19937 random(36);
    const std::string alphabet = "<>/=\"' \n-.0123456789eE+naAVP&;#";
    for (int round = 0; round < 3000; ++round) {
        std::string text = kPresets;
        for (int k = 0, changes = 1 + round % 4; k < changes; ++k) {
            const size_t at = random() % text.size();
            switch (random() % 3) {
            case 0:
                text[at] = alphabet[random() % alphabet.size()];
                break;
            case 1:
                text.erase(at, 1 + random() % 8);
                break;
            default:
                text.insert(at, 1, alphabet[random() % alphabet.size()]);
            }
        }
        tryParse(text);
    }
    EXPECT_GT(accepted, 100u) << "the mutations break every file: the test no longer tests parsing";
    EXPECT_GT(refused, 100u);
}
