// Sessions: a saved session opens to the same state, a file that is wrong anywhere is refused naming
// the field and leaves the state alone, and saving never costs the old file.
#include "imgui_null.h"
#include "file_size_limit.h"
#include "test_paths.h"
#include "ui/panels.h"
#include "ui/session.h"

#include "renderer/errors.h"
#include "renderer/io/volume_io.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

namespace {

using testing::HasSubstr;

// The TF panel shown over the window 0..1, with no histogram and no Rescale ranges.
ui::TransferFunctionView unitWindowView() {
    ui::TransferFunctionView view;
    view.window = {0.0f, 1.0f};
    return view;
}

// A state with every saved field away from its default.
ui::EditorState unusualState() {
    ui::EditorState s;
    s.tf = renderer::builtinPreset("fire");
    s.tf.colours[2].colour = {0.25, 0.5, 0.75};
    s.window.mode = renderer::WindowMode::Custom;
    s.window.custom = {-500.0f, 1500.0f};
    s.camera.azimuthDeg = -123.5;
    s.camera.elevationDeg = 44.0;
    s.camera.distance = 3.25;
    s.camera.fovYDeg = 55.0;
    s.camera.panPx = {12.0, -7.5};
    s.camera.up = {0.0, -1.0, 0.0};
    s.camera.orthographic = true;
    renderer::SplatSettings& p = s.settings;
    p.kernelScale = 0.9;
    p.cutoffSigmas = 2.5;
    p.density = 0.08;
    p.filter = renderer::FilterMode::Adaptive;
    p.cMin = 0.5;
    p.cMax = 3.0;
    p.patchSize = 4;
    p.hysteresis = 0.2;
    p.compositing = renderer::Compositing::SheetFrontToBack;
    p.primitive = renderer::SplatSettings::Primitive::Tiles;
    p.opaqueAlpha = 0.95;
    p.opaqueRefreshSlices = 3;
    p.occlusionCulling = false;
    p.shading = renderer::SplatSettings::Shading::PerFragment;
    p.shadingParams.specular = 0.6;
    p.surfaceFlatten = 4.0;
    p.surfaceGradient = 0.3;
    p.counters = true;
    s.showHeatmap = p.heatmap = true;
    s.heatmapOpacity = 0.35;
    s.histogramLog = false;
    s.background = {0.5f, 0.25f, 0.0f};
    s.spaceMouse = {.enabled = false, .speed = 2.5, .invertRotation = true, .invertTranslation = true};
    s.slabs = {.enabled = true, .thickness = 0.25, .postClassified = false, .status = {}};
    s.split = {.enabled = true,
               .imagePanes = 4,
               .panes = {ui::SplitPane{renderer::FilterMode::LowPass, renderer::Compositing::XRay},
                         ui::SplitPane{renderer::FilterMode::Adaptive, renderer::Compositing::SheetBackToFront},
                         ui::SplitPane{renderer::FilterMode::Ewa, renderer::Compositing::SplatEverySample},
                         ui::SplitPane{renderer::FilterMode::Reconstruction, renderer::Compositing::XRay}},
               .difference = ui::SplitDifference::AgainstTruth};
    return s;
}

void expectSameSession(const ui::EditorState& a, const ui::EditorState& b) {
    EXPECT_EQ(a.tf.name, b.tf.name);
    EXPECT_EQ(a.tf.colours, b.tf.colours);
    EXPECT_EQ(a.tf.opacities, b.tf.opacities);
    EXPECT_EQ(a.tf.windowFractions, b.tf.windowFractions);
    EXPECT_EQ(a.window.mode, b.window.mode);
    EXPECT_EQ(a.window.custom.lo, b.window.custom.lo);
    EXPECT_EQ(a.window.custom.hi, b.window.custom.hi);
    EXPECT_EQ(a.camera.azimuthDeg, b.camera.azimuthDeg);
    EXPECT_EQ(a.camera.elevationDeg, b.camera.elevationDeg);
    EXPECT_EQ(a.camera.distance, b.camera.distance);
    EXPECT_EQ(a.camera.fovYDeg, b.camera.fovYDeg);
    EXPECT_EQ(a.camera.panPx, b.camera.panPx);
    EXPECT_EQ(a.camera.up, b.camera.up);
    EXPECT_EQ(a.camera.orthographic, b.camera.orthographic);
    const renderer::SplatSettings &p = a.settings, &q = b.settings;
    EXPECT_EQ(p.kernelScale, q.kernelScale);
    EXPECT_EQ(p.cutoffSigmas, q.cutoffSigmas);
    EXPECT_EQ(p.density, q.density);
    EXPECT_EQ(p.filter, q.filter);
    EXPECT_EQ(p.cMin, q.cMin);
    EXPECT_EQ(p.cMax, q.cMax);
    EXPECT_EQ(p.patchSize, q.patchSize);
    EXPECT_EQ(p.hysteresis, q.hysteresis);
    EXPECT_EQ(p.compositing, q.compositing);
    EXPECT_EQ(p.primitive, q.primitive);
    EXPECT_EQ(p.opaqueAlpha, q.opaqueAlpha);
    EXPECT_EQ(p.opaqueRefreshSlices, q.opaqueRefreshSlices);
    EXPECT_EQ(p.occlusionCulling, q.occlusionCulling);
    EXPECT_EQ(p.shading, q.shading);
    EXPECT_EQ(p.shadingParams.ambient, q.shadingParams.ambient);
    EXPECT_EQ(p.shadingParams.specular, q.shadingParams.specular);
    EXPECT_EQ(p.shadingParams.shininess, q.shadingParams.shininess);
    EXPECT_EQ(p.surfaceFlatten, q.surfaceFlatten);
    EXPECT_EQ(p.surfaceGradient, q.surfaceGradient);
    EXPECT_EQ(p.counters, q.counters);
    EXPECT_EQ(p.heatmap, q.heatmap);
    EXPECT_EQ(a.showHeatmap, b.showHeatmap);
    EXPECT_EQ(a.heatmapOpacity, b.heatmapOpacity);
    EXPECT_EQ(a.histogramLog, b.histogramLog);
    EXPECT_EQ(a.background, b.background);
    EXPECT_EQ(a.spaceMouse.enabled, b.spaceMouse.enabled);
    EXPECT_EQ(a.spaceMouse.speed, b.spaceMouse.speed);
    EXPECT_EQ(a.spaceMouse.invertRotation, b.spaceMouse.invertRotation);
    EXPECT_EQ(a.spaceMouse.invertTranslation, b.spaceMouse.invertTranslation);
    EXPECT_EQ(a.split.enabled, b.split.enabled);
    EXPECT_EQ(a.split.imagePanes, b.split.imagePanes);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(a.split.panes[i].filter, b.split.panes[i].filter) << "pane " << i;
        EXPECT_EQ(a.split.panes[i].compositing, b.split.panes[i].compositing) << "pane " << i;
    }
    EXPECT_EQ(a.split.difference, b.split.difference);
    EXPECT_EQ(a.slabs.enabled, b.slabs.enabled);
    EXPECT_EQ(a.slabs.thickness, b.slabs.thickness);
    EXPECT_EQ(a.slabs.postClassified, b.slabs.postClassified);
}

std::string readText(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

} // namespace

TEST(Session, SavedStateOpensAgainFieldForFieldWithTheVolumeBesideIt) {
    const auto dir = testing_support::testOutputDir("session");
    std::filesystem::create_directories(dir / "data");
    const auto volume = dir / "data" / "scan.nhdr";
    const ui::EditorState saved = unusualState();
    ui::saveSession(saved, volume, dir / "s.json");
    // The volume is stored relative to the session, so the two can move together.
    EXPECT_THAT(readText(dir / "s.json"), HasSubstr("\"volume\": \"data/scan.nhdr\""));

    ui::EditorState opened;
    opened.errorMessage = "kept";   // not part of a session
    const std::filesystem::path v = ui::loadSession(dir / "s.json", opened);
    EXPECT_TRUE(std::filesystem::equivalent(v.parent_path(), volume.parent_path()));
    EXPECT_EQ(v.filename(), "scan.nhdr");
    expectSameSession(opened, saved);
    EXPECT_EQ(opened.errorMessage, "kept");

    // Moved elsewhere with its data, it still finds the volume.
    std::filesystem::remove_all(dir / "moved");
    std::filesystem::create_directories(dir / "moved");
    std::filesystem::copy_file(dir / "s.json", dir / "moved" / "s.json");
    EXPECT_EQ(ui::loadSession(dir / "moved" / "s.json", opened).lexically_relative(dir / "moved"), "data/scan.nhdr");
}

TEST(Session, SectionsLeftOutKeepTheStateAndUnknownKeysAreIgnored) {
    const auto dir = testing_support::testOutputDir("session");
    std::ofstream(dir / "partial.json") << R"({"splatlab_session": 1, "camera": {"distance": 4}, "extra": [1, 2]})";
    ui::EditorState state = unusualState();
    const std::filesystem::path v = ui::loadSession(dir / "partial.json", state);
    EXPECT_TRUE(v.empty());
    ui::EditorState expected = unusualState();
    expected.camera.distance = 4.0;
    expectSameSession(state, expected);
}

// Sessions written before the four panes and the truth pane (difference true or false, panes A and B only)
// still open: two panes, |A - B| or none.
TEST(Session, AnOlderSplitViewStillOpensAsTwoPanesAndItsDifference) {
    const auto dir = testing_support::testOutputDir("session");
    for (const auto& [difference, expected] : {std::pair{"true", ui::SplitDifference::AgainstB},
                                                std::pair{"false", ui::SplitDifference::Off}}) {
        std::ofstream(dir / "old_split.json")
            << R"({"splatlab_session": 1, "split": {"enabled": true, "filter_a": "ewa", "compositing_a": "xray",
                  "filter_b": "low-pass", "compositing_b": "sheet-back-to-front", "difference": )"
            << difference << "}}";
        ui::EditorState state;
        ui::loadSession(dir / "old_split.json", state);
        EXPECT_TRUE(state.split.enabled);
        EXPECT_EQ(state.split.imagePanes, 2);
        EXPECT_EQ(state.split.shownImagePanes(), 2);
        EXPECT_EQ(state.split.panes[0].filter, renderer::FilterMode::Ewa);
        EXPECT_EQ(state.split.panes[0].compositing, renderer::Compositing::XRay);
        EXPECT_EQ(state.split.panes[1].filter, renderer::FilterMode::LowPass);
        EXPECT_EQ(state.split.difference, expected) << difference;
    }
}

// A path of 10 MB in a session comes back as one short line: quoted input is cut at 200 characters.
TEST(Session, AHugeQuotedValueComesBackCutShort) {
    const auto dir = testing_support::testOutputDir("session");
    const std::string huge(10'000'000, 'a');
    std::ofstream(dir / "huge_path.json") << R"({"splatlab_session": 1, "volume": ")" << huge << R"(.raw"})";
    ui::EditorState state;
    try {
        const std::filesystem::path volume = ui::loadSession(dir / "huge_path.json", state);
        renderer::loadVolume(volume);
        ADD_FAILURE() << "loaded a volume of a 10 MB name";
    } catch (const renderer::LoadError& e) {
        EXPECT_LT(std::string(e.what()).size(), 1000u);
        EXPECT_THAT(e.what(), HasSubstr("characters)"));
    }
    const renderer::LoadError error(std::string(300, 'p'), "field", std::string(5000, 'r'));
    EXPECT_LT(std::string(error.what()).size(), 1000u);
    EXPECT_EQ(error.path().size(), 300u) << "the whole path stays for callers";
}

TEST(Session, AWrongValueAnywhereIsRefusedNamingTheFieldAndChangesNothing) {
    const auto dir = testing_support::testOutputDir("session");
    const std::pair<const char*, const char*> bad[] = {
        {"{", "not valid JSON"},
        {"[1]", "expected a JSON object"},
        {R"({"camera": {}})", "splatlab_session"},
        {R"({"splatlab_session": 99})", "newer"},
        {R"({"splatlab_session": 18446744073709551615})", "newer"},   // 2^64-1: read as -1 by a signed cast
        {R"({"splatlab_session": -5})", "expected a whole number from 1"},
        {R"({"splatlab_session": 0})", "expected a whole number from 1"},
        {R"({"splatlab_session": 1.5})", "expected a whole number from 1"},
        {R"({"splatlab_session": 1, "volume": 3})", "'volume'"},
        {R"({"splatlab_session": 1, "camera": []})", "'camera'"},
        {R"({"splatlab_session": 1, "camera": {"distance": -1}})", "'camera.distance'"},
        {R"({"splatlab_session": 1, "camera": {"fov": "wide"}})", "'camera.fov'"},
        {R"({"splatlab_session": 1, "camera": {"up": [0, 0, 0]}})", "'camera.up'"},
        {R"({"splatlab_session": 1, "camera": {"pan": [1]}})", "'camera.pan'"},
        {R"({"splatlab_session": 1, "window": {"mode": "custom", "lo": 5, "hi": 5}})", "'window.hi'"},
        {R"({"splatlab_session": 1, "window": {"mode": "sideways"}})", "'window.mode'"},
        {R"({"splatlab_session": 1, "splatting": {"filter": "sharp"}})", "'splatting.filter'"},
        {R"({"splatlab_session": 1, "splatting": {"patch_size": 2.5}})", "'splatting.patch_size'"},
        {R"({"splatlab_session": 1, "splatting": {"kernel_scale": 1e400}})", "not valid JSON"},
        {R"({"splatlab_session": 1, "splatting": {"density": 0}})", "'splatting.density'"},
        {R"({"splatlab_session": 1, "splatting": {"compositing": "splat-every-sample", "primitive": "tiles"}})",
         "'splatting.primitive'"},
        {R"({"splatlab_session": 1, "splatting": {"counters": 1}})", "'splatting.counters'"},
        {R"({"splatlab_session": 1, "view": {"background": [0, 2, 0]}})", "'view.background'"},
        {R"({"splatlab_session": 1, "space_mouse": {"speed": 0}})", "'space_mouse.speed'"},
        {R"({"splatlab_session": 1, "slabs": {"thickness": 0.01}})", "'slabs.thickness'"},
        {R"({"splatlab_session": 1, "slabs": {"post_classified": "yes"}})", "'slabs.post_classified'"},
        {R"({"splatlab_session": 1, "split": {"filter_b": "sharp"}})", "'split.filter_b'"},
        {R"({"splatlab_session": 1, "split": {"compositing_a": 2}})", "'split.compositing_a'"},
        {R"({"splatlab_session": 1, "split": {"enabled": "yes"}})", "'split.enabled'"},
        {R"({"splatlab_session": 1, "split": {"panes": 3}})", "'split.panes'"},
        {R"({"splatlab_session": 1, "split": {"difference": "c"}})", "'split.difference'"},
        {R"({"splatlab_session": 1, "split": {"filter_d": "sharp"}})", "'split.filter_d'"},
        {R"({"splatlab_session": 1, "transfer_function": {"points": []}})", "no control points"},
    };
    for (auto [text, expected] : bad) {
        std::ofstream(dir / "bad_session.json") << text;
        ui::EditorState state = unusualState();
        try {
            ui::loadSession(dir / "bad_session.json", state);
            ADD_FAILURE() << "accepted: " << text;
        } catch (const renderer::LoadError& e) {
            EXPECT_THAT(e.what(), HasSubstr("bad_session.json")) << text;
            EXPECT_THAT(e.what(), HasSubstr(expected)) << text;
        }
        expectSameSession(state, unusualState());
    }
    ui::EditorState state;
    EXPECT_THROW(ui::loadSession(dir / "no_such_session.json", state), renderer::LoadError);
}

TEST(Session, MangledFilesAreOpenedOrRefusedNeverAnythingElse) {
    // A saved session with random bytes changed, cut or repeated: each loads or throws LoadError.
    const auto dir = testing_support::testOutputDir("session");
    ui::saveSession(unusualState(), dir / "data" / "scan.nhdr", dir / "good.json");
    const std::string good = readText(dir / "good.json");
    std::mt19937 rng(11);
    int opened = 0, refused = 0;
    for (int i = 0; i < 3000; ++i) {
        std::string text = good;
        const int edits = 1 + int(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const size_t at = rng() % text.size();
            switch (rng() % 3) {
            case 0: text[at] = char(rng() % 128); break;
            case 1: text.erase(at, 1 + rng() % 8); break;
            default: text.insert(at, text.substr(rng() % text.size(), 1 + rng() % 16)); break;
            }
            if (text.empty()) text = "{";
        }
        std::ofstream(dir / "mangled.json", std::ios::trunc) << text;
        ui::EditorState state;
        try {
            ui::loadSession(dir / "mangled.json", state);
            ++opened;
        } catch (const renderer::LoadError&) {
            ++refused;
        }
    }
    EXPECT_GT(opened, 0);
    EXPECT_GT(refused, 0);
}

TEST(Session, AFolderInsteadOfASessionIsNamed) {
    const auto dir = testing_support::testOutputDir("session") / "a_folder.json";
    std::filesystem::create_directories(dir);
    ui::EditorState state;
    try {
        ui::loadSession(dir, state);
        ADD_FAILURE() << "opened a folder as a session";
    } catch (const renderer::LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr("a_folder.json: is a folder, expected a SplatLab session"));
    }
}

TEST(Session, AFailedSaveKeepsTheOldFile) {
    const auto dir = testing_support::testOutputDir("session");
    ui::saveSession(unusualState(), {}, dir / "keep.json");
    const std::string before = readText(dir / "keep.json");
    {   // A full disk: the temporary file cannot be written whole.
        const testing_support::FileSizeLimit fullDisk(256);
        ASSERT_TRUE(fullDisk.active());
        EXPECT_THROW(ui::saveSession(ui::EditorState{}, {}, dir / "keep.json"), renderer::LoadError);
    }
    EXPECT_EQ(readText(dir / "keep.json"), before);
    try {
        ui::saveSession(ui::EditorState{}, {}, dir / "missing" / "s.json");
        ADD_FAILURE() << "saved into a folder that does not exist";
    } catch (const renderer::LoadError& e) {
        EXPECT_THAT(e.what(), HasSubstr("s.json"));
    }
}

// == Through the Settings panel

TEST_F(ImGuiNull, SessionButtonsSaveAndOpenAndABadFileOpensTheErrorDialogInstead) {
    const auto dir = testing_support::testOutputDir("session");
    ui::EditorState state = unusualState();
    state.loadedVolume = dir / "data" / "scan.nhdr";
    state.sessionFile = (dir / "panel.json").string();
    std::filesystem::remove(dir / "panel.json");
    ui::SettingsChanges changes;
    ImGuiID openId = 0, saveId = 0;
    auto body = [&] {
        openId = ImGui::GetID("Open session");
        saveId = ImGui::GetID("Save session");
        const ui::SettingsChanges c = ui::drawSettingsPanel(state);
        changes.sessionOpened |= c.sessionOpened;
        if (c.sessionOpened) changes.sessionVolume = c.sessionVolume;
    };
    frame(body);
    const float y = findItem(openId, 20.0f, 0.0f, 700.0f, body);
    ASSERT_GE(y, 0.0f) << "no Open session button";
    const float saveX = findItemInRow(saveId, y, body);
    ASSERT_GE(saveX, 0.0f) << "no Save session button";

    click(saveX, y, body);
    ASSERT_TRUE(state.errorMessage.empty()) << state.errorMessage;
    ASSERT_TRUE(std::filesystem::exists(dir / "panel.json"));

    const std::string sessionFile = state.sessionFile;
    state = ui::EditorState{};
    state.sessionFile = sessionFile;
    click(20.0f, y, body);
    EXPECT_TRUE(changes.sessionOpened);
    EXPECT_EQ(changes.sessionVolume.filename(), "scan.nhdr");
    expectSameSession(state, unusualState());

    std::ofstream(dir / "panel_bad.json") << R"({"splatlab_session": 1, "camera": {"distance": "far"}})";
    state.sessionFile = (dir / "panel_bad.json").string();
    changes = {};
    click(20.0f, y, body);
    EXPECT_FALSE(changes.sessionOpened);
    EXPECT_THAT(state.errorMessage, HasSubstr("panel_bad.json"));
    EXPECT_THAT(state.errorMessage, HasSubstr("camera.distance"));
    expectSameSession(state, unusualState());
}

// == Files dropped on the window

TEST_F(ImGuiNull, ADroppedFileOpensAsItsPanelsButtonWouldOnce) {
    const auto dir = testing_support::testOutputDir("session");
    const auto volume = dir / "data" / "scan.nhdr";
    ui::EditorState state;
    ui::SettingsChanges changes;
    bool tfChanged = false;
    auto settings = [&] {
        const ui::SettingsChanges c = ui::drawSettingsPanel(state);
        changes.openVolume |= c.openVolume;
        changes.sessionOpened |= c.sessionOpened;
    };
    auto transferFunction = [&] { tfChanged |= ui::drawTransferFunctionPanel(state, unitWindowView()); };

    frame(transferFunction);   // the first frame fixes the preset's window fractions in data units
    tfChanged = false;
    // A volume: Settings' Open volume, pressed once.
    EXPECT_STREQ(ui::dropFile(state, volume), "Settings");
    EXPECT_EQ(state.volumeFile, volume.string());
    frame(transferFunction);   // another panel leaves it alone
    EXPECT_FALSE(tfChanged);
    frame(settings);
    EXPECT_TRUE(changes.openVolume);
    changes = {};
    frame(settings);
    EXPECT_FALSE(changes.openVolume);

    // A session (JSON naming itself one): Open session, the state becomes the saved one.
    const ui::EditorState saved = unusualState();
    ui::saveSession(saved, volume, dir / "dropped.json");
    EXPECT_STREQ(ui::dropFile(state, dir / "dropped.json"), "Settings");
    frame(settings);
    EXPECT_TRUE(changes.sessionOpened);
    EXPECT_EQ(state.camera.azimuthDeg, saved.camera.azimuthDeg);
    EXPECT_TRUE(state.errorMessage.empty()) << state.errorMessage;

    // Any other JSON: the transfer function's Load.
    state = ui::EditorState{};
    renderer::saveTransferFunction(renderer::builtinPreset("soft"), dir / "dropped_tf.JSON");
    EXPECT_STREQ(ui::dropFile(state, dir / "dropped_tf.JSON"), "Transfer function");
    frame(transferFunction);
    EXPECT_TRUE(tfChanged);
    EXPECT_EQ(state.tf.opacities.size(), renderer::builtinPreset("soft").opacities.size());
    EXPECT_EQ(state.tf.opacities.back().opacity, renderer::builtinPreset("soft").opacities.back().opacity);
    EXPECT_EQ(state.pendingFile, ui::FileAction::None);

    // A JSON that does not parse: the TF loader's error, naming the file.
    std::ofstream(dir / "broken.json") << "{";
    ui::dropFile(state, dir / "broken.json");
    frame(transferFunction);
    EXPECT_THAT(state.errorMessage, HasSubstr("broken.json"));
}
