// numberField: a plain click on a numeric field types into it, a drag still changes the value, and a
// click no longer moves a slider to where it landed. Driven through ImGui with synthetic input.
#include "imgui_null.h"
#include "ui/number_field.h"

#include <gtest/gtest.h>

namespace {

class NumberField : public ImGuiNull {
  protected:
    double slider = 0.25; // a slider over 0 .. 1
    float drag = 5.0f;    // a drag field, 0.1 per pixel
    int changes = 0;
    std::function<void()> body() {
        return [this] {
            const double lo = 0.0, hi = 1.0;
            changes += ui::numberField("Slider", slider, [&] {
                return ImGui::SliderScalar("Slider", ImGuiDataType_Double, &slider, &lo, &hi, "%.3f");
            });
            changes += ui::numberField("Drag", drag, [&] { return ImGui::DragFloat("Drag", &drag, 0.1f); });
        };
    }
    // The y of the field `label` in the panel's first column of widgets.
    float find(const char* label) {
        ImGuiID id = 0;
        frame([&] { id = ImGui::GetID(label); });
        return findItem(id, 30.0f, 0.0f, 200.0f, body());
    }
    void type(const char* text) {
        for (const char* c = text; *c; ++c)
            ImGui::GetIO().AddInputCharacter(unsigned(*c));
        frame(body());
        ImGuiIO& io = ImGui::GetIO();
        io.KeyMap[ImGuiKey_Enter] = 13;
        io.KeysDown[13] = true;
        frame(body());
        io.KeysDown[13] = false;
        frame(body());
    }
    bool typing() const {
        const ImGuiContext& g = *ImGui::GetCurrentContext();
        return g.TempInputId != 0 && g.ActiveId == g.TempInputId;
    }
};

} // namespace

TEST_F(NumberField, APlainClickOnASliderTypesAndEnterSetsExactlyWhatWasTyped) {
    const float y = find("Slider");
    ASSERT_GE(y, 0.0f) << "no slider";
    click(30.0f, y, body()); // near the slider's left end: ImGui alone would set about 0.05
    EXPECT_EQ(slider, 0.25) << "a click must not move the slider";
    EXPECT_EQ(changes, 0);
    frame(body()); // the text input opens the frame after the release
    ASSERT_TRUE(typing()) << "a plain click must open the text input";
    type("0.8123");
    EXPECT_FALSE(typing());
    EXPECT_EQ(slider, 0.8123);
    EXPECT_GT(changes, 0);
}

TEST_F(NumberField, APlainClickOnADragFieldTypesToo) {
    const float y = find("Drag");
    ASSERT_GE(y, 0.0f) << "no drag field";
    click(100.0f, y, body());
    frame(body());
    ASSERT_TRUE(typing());
    type("-12.5");
    EXPECT_EQ(drag, -12.5f);
}

TEST_F(NumberField, ADragStillChangesTheValueAndOpensNoTextInput) {
    const float sliderY = find("Slider"), dragY = find("Drag");
    ASSERT_GE(sliderY, 0.0f);
    ASSERT_GE(dragY, 0.0f);
    // The slider: press near its left end, drag right 150 px, release.
    mouse(30.0f, sliderY, true);
    frame(body());
    for (float x = 40.0f; x <= 180.0f; x += 10.0f) {
        mouse(x, sliderY, true);
        frame(body());
    }
    mouse(180.0f, sliderY, false);
    frame(body());
    frame(body());
    EXPECT_NE(slider, 0.25);
    EXPECT_FALSE(typing()) << "a drag must not open the text input";
    // The drag field: 50 px to the right at 0.1 per pixel.
    const float before = drag;
    mouse(100.0f, dragY, true);
    frame(body());
    for (float x = 110.0f; x <= 150.0f; x += 10.0f) {
        mouse(x, dragY, true);
        frame(body());
    }
    mouse(150.0f, dragY, false);
    frame(body());
    frame(body());
    EXPECT_GT(drag, before + 1.0f);
    EXPECT_FALSE(typing());
}

// While one field takes text, a click on another ends that typing (keeping its value) and the field
// clicked is the one that types next.
TEST_F(NumberField, AClickOnAnotherFieldWhileTypingMovesTheTypingThere) {
    const float sliderY = find("Slider"), dragY = find("Drag");
    click(30.0f, sliderY, body());
    frame(body());
    ASSERT_TRUE(typing());
    click(100.0f, dragY, body());
    frame(body());
    ASSERT_TRUE(typing());
    type("7");
    EXPECT_EQ(drag, 7.0f);
    EXPECT_EQ(slider, 0.25);
}
