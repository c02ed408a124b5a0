// A test fixture that drives panels through ImGui with no renderer backend: mouse events in, the
// panels' structs out, no pixels. Widget positions come from ImGui's own layout, found by hovering.
#pragma once
#include "ui/dock_layout.h"   // ui::Rect

#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <functional>
#include <string>

class ImGuiNull : public testing::Test {
  protected:
    void SetUp() override {
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.DisplaySize = ImVec2(1280, 800);
        io.DeltaTime = 1.0f / 60.0f;
        io.IniFilename = nullptr;
        unsigned char* pixels = nullptr;
        int w = 0, h = 0;
        io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h); // builds the atlas; nothing uploads it
        ImGui::GetStyle().AntiAliasedLinesUseTex = false;   // only glyphs sample the atlas (textCutOff)
    }
    void TearDown() override { ImGui::DestroyContext(); }

    float windowWidth = 400, windowHeight = 700;
    // One frame with `body` inside a fixed windowWidth x windowHeight window at the origin.
    void frame(const std::function<void()>& body) {
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImVec2(windowWidth, windowHeight));
        ImGui::Begin("Panel", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
        body();
        ImGui::End();
        ImGui::Render();
    }
    // The text `body` draws in one frame, as ImGui's log writes it (lines, table columns between " | ").
    std::string loggedText(const std::function<void()>& body) {
        std::string captured;
        frame([&] {
            ImGui::LogToBuffer();
            body();
            captured = ImGui::GetCurrentContext()->LogBuffer.c_str();
            ImGui::LogFinish();
        });
        return captured;
    }
    // After a frame: the first glyph drawn past the right edge of its clip rectangle (text a column or
    // window cuts off), as "x at y past clip edge", or "" when all text fits. Widgets that clip text on
    // purpose (a combo's preview) clip it on the CPU, so their glyphs never cross the edge.
    static std::string textCutOff() {
        const ImVec2 white = ImGui::GetIO().Fonts->TexUvWhitePixel;
        const ImDrawData* data = ImGui::GetDrawData();
        for (int l = 0; l < data->CmdListsCount; ++l) {
            const ImDrawList* list = data->CmdLists[l];
            for (const ImDrawCmd& cmd : list->CmdBuffer)
                for (unsigned i = 0; i < cmd.ElemCount; ++i) {
                    const ImDrawVert& v = list->VtxBuffer[int(cmd.VtxOffset + list->IdxBuffer[int(cmd.IdxOffset + i)])];
                    const bool glyph = v.uv.x != white.x || v.uv.y != white.y;
                    if (glyph && v.pos.x > cmd.ClipRect.z + 1.0f && v.pos.y < cmd.ClipRect.w)
                        return std::to_string(v.pos.x) + " at y " + std::to_string(v.pos.y) + " past " +
                               std::to_string(cmd.ClipRect.z);
                }
        }
        return "";
    }
    void mouse(float x, float y, bool down) {
        ImGui::GetIO().MousePos = ImVec2(x, y);
        ImGui::GetIO().MouseDown[0] = down;
    }
    // Presses and releases the left button at (x, y), a frame each.
    void click(float x, float y, const std::function<void()>& body) {
        mouse(x, y, true);
        frame(body);
        mouse(x, y, false);
        frame(body);
    }
    // Moves the mouse down the column x = `x` between y0 and y1 until the item `id` is hovered; returns
    // the y where it was, or -1. Widget positions come from ImGui's own layout, not from constants.
    float findItem(ImGuiID id, float x, float y0, float y1, const std::function<void()>& body) {
        for (float y = y0; y < y1; y += 2.0f) {
            mouse(x, y, false);
            frame(body);
            if (ImGui::GetCurrentContext()->HoveredId == id) return y;
        }
        return -1.0f;
    }
    // The same along the row y = `y` (items laid out side by side); returns the x, or -1.
    float findItemInRow(ImGuiID id, float y, const std::function<void()>& body) {
        for (float x = 0.0f; x < 400.0f; x += 2.0f) {
            mouse(x, y, false);
            frame(body);
            if (ImGui::GetCurrentContext()->HoveredId == id) return x;
        }
        return -1.0f;
    }
    // The rectangle of the item `id` (a canvas), found by hovering: its first and last hovered pixels
    // down the column x = 200 (to y = maxY), then across the row through its middle. `id` is read after
    // each frame, so the body may be what sets it.
    ui::Rect findItemRect(const ImGuiID& id, float maxY, const std::function<void()>& body) {
        frame(body);
        float top = -1, bottom = -1, left = -1, right = -1;
        for (float y = 0; y < maxY; y += 1) {
            mouse(200, y, false);
            frame(body);
            if (ImGui::GetCurrentContext()->HoveredId == id) (top < 0 ? top : bottom) = y;
        }
        const float mid = (top + bottom) * 0.5f;
        for (float x = 0; x < 400; x += 1) {
            mouse(x, mid, false);
            frame(body);
            if (ImGui::GetCurrentContext()->HoveredId == id) (left < 0 ? left : right) = x;
        }
        return {left, top, right + 1 - left, bottom + 1 - top};
    }
};
