// The save confirmation: each save the editor makes from a panel (TF, session, CSV; the image's comes
// from the app) shows "Saved FILE" in the corner, which fades after a few seconds; a failed save shows
// the error modal naming the file and no confirmation.
#include "imgui_null.h"
#include "test_paths.h"
#include "ui/panels.h"
#include "ui/save_notice.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace {

using testing::HasSubstr;

class SaveNoticeTest : public ImGuiNull {
  protected:
    ui::EditorState state;
    ImGuiID loadId = 0, saveId = 0;
    // The TF panel, as the editor draws it, and the notice over it.
    std::function<void()> body() {
        return [this] {
            loadId = ImGui::GetID("Load");
            saveId = ImGui::GetID("Save");
            ui::TransferFunctionView view;
            view.window = {-1000.0f, 3000.0f};
            ui::drawTransferFunctionPanel(state, view);
            ui::drawSaveNotice(state.saveNotice);
        };
    }
    bool noticeShown() const {
        const ImGuiWindow* window = ImGui::FindWindowByName("##save_notice");
        return window && window->Active;
    }
    // Clicks the TF panel's Save button, found beside Load.
    void clickSave() {
        frame(body());
        const float y = findItem(loadId, 20.0f, 0.0f, 700.0f, body());
        ASSERT_GE(y, 0.0f) << "no Load button";
        const float x = findItemInRow(saveId, y, body());
        ASSERT_GE(x, 0.0f) << "no Save button";
        click(x, y, body());
    }
};

} // namespace

TEST(SaveNotice, NamesTheFileAndItsFolderAndFadesAfterItsTime) {
    const ui::SaveNotice notice = ui::savedNotice(std::filesystem::path("out") / "view.png", "640 x 480");
    EXPECT_EQ(notice.text, "Saved view.png (640 x 480)");
    EXPECT_EQ(notice.folder, "in out");
    EXPECT_EQ(ui::savedNotice("tf.json").folder, "in the current folder");
    EXPECT_EQ(ui::saveNoticeAlpha(0.0), 1.0f);
    EXPECT_EQ(ui::saveNoticeAlpha(ui::SaveNotice::kShownS), 1.0f);
    EXPECT_NEAR(ui::saveNoticeAlpha(ui::SaveNotice::kShownS + 0.5 * ui::SaveNotice::kFadeS), 0.5f, 1e-6);
    EXPECT_EQ(ui::saveNoticeAlpha(ui::SaveNotice::kShownS + ui::SaveNotice::kFadeS), 0.0f);
}

TEST_F(SaveNoticeTest, SavingATransferFunctionShowsItsNameUntilTheNoticeFades) {
    const auto dir = testing_support::testOutputDir("save_notice");
    std::filesystem::remove(dir / "bone.json");
    state.tfFile = (dir / "bone.json").string();
    clickSave();
    ASSERT_TRUE(state.errorMessage.empty()) << state.errorMessage;
    ASSERT_TRUE(std::filesystem::exists(dir / "bone.json"));
    EXPECT_EQ(state.saveNotice.text, "Saved bone.json");
    EXPECT_THAT(state.saveNotice.folder, HasSubstr("save_notice"));
    frame(body());
    EXPECT_TRUE(noticeShown());
    // Seconds pass: still there within kShownS, gone after the fade.
    ImGui::GetIO().DeltaTime = float(ui::SaveNotice::kShownS) - 0.5f;
    frame(body());
    EXPECT_TRUE(noticeShown());
    ImGui::GetIO().DeltaTime = float(ui::SaveNotice::kFadeS) + 0.5f;
    frame(body());
    ImGui::GetIO().DeltaTime = 1.0f / 60.0f;
    frame(body());
    EXPECT_FALSE(noticeShown());
    EXPECT_TRUE(state.saveNotice.text.empty());
}

TEST_F(SaveNoticeTest, AFailedSaveShowsTheErrorNamingTheFileAndNoConfirmation) {
    const auto dir = testing_support::testOutputDir("save_notice");
    state.tfFile = (dir / "no_such_folder" / "bone.json").string();
    clickSave();
    EXPECT_THAT(state.errorMessage, HasSubstr("bone.json"));
    EXPECT_TRUE(state.saveNotice.text.empty());
    frame(body());
    EXPECT_FALSE(noticeShown());
}

TEST_F(SaveNoticeTest, SavingASessionShowsItsName) {
    const auto dir = testing_support::testOutputDir("save_notice");
    state.sessionFile = (dir / "head.json").string();
    ImGuiID saveSessionId = 0, openSessionId = 0;
    auto settings = [&] {
        saveSessionId = ImGui::GetID("Save session");
        openSessionId = ImGui::GetID("Open session");
        ui::drawSettingsPanel(state);
    };
    frame(settings);
    const float y = findItem(openSessionId, 20.0f, 0.0f, 700.0f, settings);
    ASSERT_GE(y, 0.0f) << "no Open session button";
    const float x = findItemInRow(saveSessionId, y, settings);
    ASSERT_GE(x, 0.0f) << "no Save session button";
    click(x, y, settings);
    ASSERT_TRUE(state.errorMessage.empty()) << state.errorMessage;
    EXPECT_EQ(state.saveNotice.text, "Saved head.json");
}
