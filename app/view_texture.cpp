// The viewport's textures (view_texture.h).
#include "view_texture.h"

#include <epoxy/gl.h>

ViewTexture::~ViewTexture() {
    if (m_id) glDeleteTextures(1, &m_id);
}

void ViewTexture::upload(int width, int height, const std::vector<uint8_t>& rgba) {
    if (width != m_width || height != m_height || m_id == 0) {
        if (m_id) glDeleteTextures(1, &m_id);
        glCreateTextures(GL_TEXTURE_2D, 1, &m_id);
        glTextureStorage2D(m_id, 1, GL_RGBA8, width, height);
        glTextureParameteri(m_id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(m_id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        m_width = width, m_height = height;
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(m_id, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
}
