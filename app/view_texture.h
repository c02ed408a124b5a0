// A GL texture in the UI's context holding one RGBA8 image from the render thread (the viewport's image,
// or its heatmap). Made and destroyed while the window's context is current (EditorLoop owns it).
#pragma once
#include <cstdint>
#include <vector>

class ViewTexture {
  public:
    ViewTexture() = default;
    ~ViewTexture();
    ViewTexture(const ViewTexture&) = delete;
    ViewTexture& operator=(const ViewTexture&) = delete;

    // Uploads `rgba` (width x height, row 0 at the top); the texture is remade when the size changes.
    void upload(int width, int height, const std::vector<uint8_t>& rgba);
    unsigned id() const { return m_id; } // 0 until an image arrived

  private:
    unsigned m_id = 0;
    int m_width = 0, m_height = 0;
};
