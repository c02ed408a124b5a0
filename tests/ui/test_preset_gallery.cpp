// The Transfer function panel's gallery: a click on a thumbnail applies that preset, and each thumbnail the
// editor draws (on its render thread, into a UI texture) is a headless render of that preset at that size,
// within the editor-vs-render tolerance (test_cli_editor.cpp's), with the view's own LUT put back after.
#include "image_compare.h"
#include "imgui_null.h"
#include "preset_gallery.h"
#include "test_paths.h"
#include "ui/panels.h"

#include "renderer/gl/gl_context.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/io/volume_io.h"

#include <epoxy/gl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>

using renderer::TransferFunction;

namespace {

class GalleryPanel : public ImGuiNull {
  protected:
    ui::EditorState state;
    ui::TransferFunctionView view;
    bool changed = false;

    void SetUp() override {
        ImGuiNull::SetUp();
        windowHeight = 800; // the gallery comes last in the panel
        view.window = {-1000.0f, 3000.0f};
        state.tf = renderer::inDataUnits(renderer::builtinPreset("grey-ramp"), view.window);
        state.tfGalleryOpen = true;
        unsigned texture = 1; // no pixels here: any ids will do
        for (const std::string& name : renderer::builtinPresetNames())
            view.gallery.push_back({name, texture++});
    }
    std::function<void()> body() {
        return [this] { changed |= ui::drawTransferFunctionPanel(state, view); };
    }
    ImGuiID thumbnailId(const std::string& name) {
        ImGuiID id = 0;
        frame([&] {
            ImGui::PushID(name.c_str());
            id = ImGui::GetID("thumbnail");
            ImGui::PopID();
        });
        return id;
    }
};

} // namespace

TEST_F(GalleryPanel, ClickingAThumbnailAppliesThatPreset) {
    ASSERT_GE(view.gallery.size(), 3u);
    // The second thumbnail: found by hovering down the first's column, then along its row.
    const std::string first = view.gallery[0].name, second = view.gallery[1].name;
    const float y = findItem(thumbnailId(first), 40.0f, 0.0f, 780.0f, body());
    ASSERT_GE(y, 0.0f) << "no thumbnail of " << first;
    const float x = findItemInRow(thumbnailId(second), y, body());
    ASSERT_GE(x, 0.0f) << "the second thumbnail is not beside the first";
    EXPECT_FALSE(changed);
    click(x, y, body());
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf, galleryPreset(second, view.window));
    EXPECT_EQ(state.tf, renderer::inDataUnits(renderer::builtinPreset(second), view.window));
    EXPECT_FALSE(state.tfEdited);
    // And another: the first one's.
    changed = false;
    click(40.0f, y, body());
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf, galleryPreset(first, view.window));
}

// The Gallery button beside Undo and Redo opens and closes it; closed, it shows no thumbnail to click.
TEST_F(GalleryPanel, TheGalleryButtonOpensAndClosesIt) {
    state.tfGalleryOpen = false;
    EXPECT_LT(findItem(thumbnailId(view.gallery[0].name), 40.0f, 0.0f, 780.0f, body()), 0.0f);
    ImGuiID buttonId = 0, loadId = 0;
    frame([&] { buttonId = ImGui::GetID("Gallery"), loadId = ImGui::GetID("Load"); });
    // The row of Load, Save, Undo and Redo, found by Load at its left; the Gallery button along it.
    const float buttonY = findItem(loadId, 20.0f, 0.0f, 780.0f, body());
    ASSERT_GE(buttonY, 0.0f) << "no Load button";
    const float buttonX = findItemInRow(buttonId, buttonY, body());
    ASSERT_GE(buttonX, 0.0f) << "no Gallery button on Load's row";
    click(buttonX, buttonY, body());
    EXPECT_TRUE(state.tfGalleryOpen);
    EXPECT_GE(findItem(thumbnailId(view.gallery[0].name), 40.0f, buttonY, 780.0f, body()), 0.0f);
    click(buttonX, buttonY, body());
    EXPECT_FALSE(state.tfGalleryOpen);
    EXPECT_FALSE(changed) << "opening the gallery changed the TF";
}

// The editor's gallery end to end, on the bundled head CT: its render thread draws each preset into a
// texture of this test's GL context (standing for the window's), and each texture holds what a headless
// SplatRenderer draws for that preset at kThumbnailPx, over the same background.
TEST(PresetGallery, EachThumbnailIsAHeadlessRenderOfItsPreset) {
    std::unique_ptr<renderer::HeadlessGl> gl;
    std::unique_ptr<RenderThread> thread;
    try {
        gl = renderer::HeadlessGl::create();
        thread = std::make_unique<RenderThread>();
    } catch (const std::exception& e) {
        if (const char* r = std::getenv("REQUIRE_GL"); r && std::string(r) == "1") FAIL() << e.what();
        GTEST_SKIP() << "no headless GL context: " << e.what();
    }
    const renderer::Volume volume =
        renderer::loadVolume(testing_support::assetDir() / "volumes" / "headsq.nhdr");
    const renderer::ValueRange window = volume.range;
    const TransferFunction shown = galleryPreset("grey-ramp", window); // what the view shows meanwhile
    const renderer::SplatScene scene = renderer::buildSplatScene(volume, shown, window);
    thread->setScenesNow(std::make_shared<const renderer::SplatScene>(scene), {});
    thread->setLuts(renderer::tfTables(scene), {});

    ThumbnailSource source;
    source.plane = thumbnailPlane(scene, glm::dvec3(0, 0, -1)); // headsq's up
    source.window = scene.window;
    source.shownTables = renderer::tfTables(scene);
    const std::array<float, 3> background{0.1f, 0.1f, 0.12f};
    PresetGallery gallery;
    for (int step = 0; step < 40 && !gallery.complete(); ++step)
        gallery.step(*thread, source, background, true);
    ASSERT_TRUE(gallery.complete());
    const std::vector<ui::GalleryThumbnail> thumbnails = gallery.thumbnails();
    ASSERT_EQ(thumbnails.size(), renderer::builtinPresetNames().size());

    renderer::SplatRenderer headless;
    headless.setScene(scene);
    const auto toImage = [](const std::vector<uint8_t>& rgba) {
        renderer::Image image(kThumbnailPx, kThumbnailPx);
        for (size_t i = 0; i < rgba.size(); ++i)
            image.rgba[i] = float(rgba[i]) / 255.0f;
        return image;
    };
    headless.setLut(renderer::tfTables(scene));
    headless.render(source.plane, source.settings);
    const renderer::Image shownImage = toImage(overBackground(headless.readback(), background));
    size_t showing = 0;
    for (const ui::GalleryThumbnail& t : thumbnails) {
        SCOPED_TRACE(t.name);
        ASSERT_NE(t.texture, 0u);
        std::vector<uint8_t> pixels(size_t(kThumbnailPx) * kThumbnailPx * 4);
        glGetTextureImage(t.texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(pixels.size()), pixels.data());
        headless.setLut({renderer::bakeLut(galleryPreset(t.name, window), window), {}, {}});
        headless.render(source.plane, source.settings);
        const renderer::Image expected = headless.readback();
        showing += renderer::imageStats(expected).coveredFraction > 0.02;
        // Both over the background in 8 bits: the editor-vs-render tolerance (2e-3 at opaque pixels, 1e-5
        // elsewhere) moves a channel by at most one step of 8 bits.
        const renderer::ImageError e =
            renderer::compareImages(toImage(pixels), toImage(overBackground(expected, background)));
        EXPECT_LE(e.maxAbs, 1.0 / 255.0 + 1e-6);
        // Each is its own preset, not the view's TF drawn again.
        if (t.name != "grey-ramp") {
            EXPECT_GT(renderer::compareImages(toImage(pixels), shownImage).maxAbs, 0.05);
        }
    }
    EXPECT_GE(showing, 4u) << "most presets should show the head: the comparison would be of blanks";

    // The view's LUT is back: the render thread's next frame is the shown TF's.
    const renderer::Image after = thread
                                      ->run([&](Renderers& r) {
                                          r.full->render(source.plane, source.settings);
                                          return r.full->readback();
                                      })
                                      .get();
    headless.setLut(renderer::tfTables(scene));
    headless.render(source.plane, source.settings);
    const auto d = testing_support::renderDifference(after, headless.readback());
    EXPECT_LE(d.elsewhere, 1e-5f);
    EXPECT_LE(d.atOpaque, 2e-3f);
}

// A Slicer presets.xml dropped on the window goes to the TF panel's Load, which imports its first preset;
// FILE.xml#NAME typed into the File field picks another, and what the import leaves out is noted.
TEST_F(GalleryPanel, LoadImportsASlicerPresetNamedInTheFileField) {
    const auto file = testing_support::testOutputDir("slicer") / "panel_presets.xml";
    ASSERT_TRUE(testing_support::writeFile(file, R"(<MRML>
  <VolumeProperty name="Flat" scalarOpacity="4 0 0 100 0.5" colorTransfer="8 0 0 0 0 100 1 1 1"/>
  <VolumeProperty name="Edges" gradientOpacity="4 0 0 50 1" scalarOpacity="4 -500 0 900 0.8"
    colorTransfer="8 -500 1 0 0 900 1 1 0"/>
</MRML>)"));
    EXPECT_STREQ(ui::dropFile(state, file), "Transfer function");
    frame(body());
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf.name, "Flat");
    EXPECT_EQ(state.tf.opacities, (std::vector<renderer::OpacityPoint>{{0, 0.0}, {100, 0.5}}));
    EXPECT_THAT(state.saveNotice.text, testing::HasSubstr("holds 2 presets; took the first, Flat"));

    changed = false;
    state.tfFile = file.string() + "#Edges";
    state.pendingFile = ui::FileAction::LoadTransferFunction;
    frame(body());
    EXPECT_TRUE(changed);
    EXPECT_EQ(state.tf.name, "Edges");
    EXPECT_EQ(state.tf.opacities, (std::vector<renderer::OpacityPoint>{{-500, 0.0}, {900, 0.8}}));
    EXPECT_EQ(state.tf.gradientOpacity, (std::vector<renderer::GradientOpacityPoint>{{0, 0.0}, {50, 1.0}}));
    EXPECT_TRUE(state.errorMessage.empty()) << state.errorMessage;

    state.tfFile = file.string() + "#Bone";
    state.pendingFile = ui::FileAction::LoadTransferFunction;
    frame(body());
    EXPECT_THAT(state.errorMessage, testing::HasSubstr("no preset named 'Bone' (it holds: Flat, Edges)"));
    EXPECT_EQ(state.tf.name, "Edges") << "a failed load changed the TF";
}
