// The TF panel's preset thumbnails (preset_gallery.h): drawn on the render thread, kept in UI textures.
#include "preset_gallery.h"

#include "ui/panels.h"

#include "renderer/errors.h"

#include <algorithm>
#include <chrono>
#include <cmath>

renderer::ImagePlane thumbnailPlane(const renderer::SplatScene& scene, const glm::dvec3& up) {
    renderer::Camera camera;
    camera.up = up;
    return renderer::makeImagePlane(camera, scene.centre, scene.radius, kThumbnailPx, kThumbnailPx,
                                    scene.axes);
}

renderer::TransferFunction galleryPreset(const std::string& name, renderer::ValueRange window) {
    return renderer::inDataUnits(renderer::builtinPreset(name), window);
}

std::future<renderer::Image> renderThumbnail(RenderThread& thread, const ThumbnailSource& source,
                                             const renderer::TransferFunction& tf) {
    // A preset's own LUT; no gradient factors (the built-in presets have no gradient opacity).
    return thread.run([source, tables = renderer::TfTables{renderer::bakeLut(tf, source.window), {}, {}}](Renderers& r) {
        if (source.level > int(r.levels.size()))
            throw renderer::RenderError("thumbnail: no level " + std::to_string(source.level) +
                                        " to draw from");
        renderer::SplatRenderer& which = source.level == 0 ? *r.full : *r.levels[size_t(source.level - 1)];
        // The view's LUT goes back whatever happens: the next view must not show a preset.
        struct RestoreTables {
            renderer::SplatRenderer& renderer;
            const renderer::TfTables& tables;
            ~RestoreTables() { renderer.setLut(tables); }
        } restore{which, source.shownTables};
        which.setLut(tables);
        which.render(source.plane, source.settings);
        return which.readback();
    });
}

std::vector<uint8_t> overBackground(const renderer::Image& image, const std::array<float, 3>& background) {
    std::vector<uint8_t> rgba(size_t(image.width) * size_t(image.height) * 4);
    for (size_t i = 0; i < rgba.size() / 4; ++i) {
        const float* p = &image.rgba[i * 4];
        for (int c = 0; c < 3; ++c) {
            const float v = p[c] + (1.0f - p[3]) * background[size_t(c)];
            rgba[i * 4 + size_t(c)] =
                uint8_t(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
        }
        rgba[i * 4 + 3] = 255;
    }
    return rgba;
}

void PresetGallery::invalidate() {
    m_entries.clear();
    ++m_generation;
}

bool PresetGallery::step(RenderThread& thread, const ThumbnailSource& source,
                         const std::array<float, 3>& background, bool wait) {
    // 1. The presets, named afresh after each invalidate() (a file added to assets/presets shows up).
    if (m_entries.empty())
        for (const std::string& name : renderer::builtinPresetNames())
            m_entries.push_back({name, nullptr});
    // 2. A finished thumbnail into its texture, if it is of the volume and window shown.
    bool arrived = false;
    if (m_pending &&
        (wait || m_pending->image.wait_for(std::chrono::seconds(0)) == std::future_status::ready)) {
        Pending done = std::move(*m_pending);
        m_pending.reset();
        try {
            const renderer::Image image = done.image.get();
            if (done.generation == m_generation && done.entry < m_entries.size()) {
                auto texture = std::make_unique<ViewTexture>();
                texture->upload(image.width, image.height, overBackground(image, background));
                m_entries[done.entry].texture = std::move(texture);
                arrived = true;
            }
        } catch (const std::exception&) { // out of memory, a GL error: that preset shows no thumbnail
            if (done.generation == m_generation && done.entry < m_entries.size())
                m_entries[done.entry].failed = true;
        }
    }
    // 3. The next missing one.
    if (!m_pending) {
        const auto next = std::find_if(m_entries.begin(), m_entries.end(),
                                       [](const Entry& e) { return !e.texture && !e.failed; });
        if (next != m_entries.end()) {
            try {
                m_pending =
                    Pending{size_t(next - m_entries.begin()), m_generation,
                            renderThumbnail(thread, source, galleryPreset(next->name, source.window))};
            } catch (const std::exception&) { // a bundled preset file that no longer reads
                next->failed = true;
            }
        }
    }
    return arrived;
}

bool PresetGallery::complete() const {
    return !m_entries.empty() && std::all_of(m_entries.begin(), m_entries.end(),
                                             [](const Entry& e) { return e.texture || e.failed; });
}

std::vector<ui::GalleryThumbnail> PresetGallery::thumbnails() const {
    std::vector<ui::GalleryThumbnail> shown;
    for (const Entry& e : m_entries)
        shown.push_back({e.name, e.texture ? e.texture->id() : 0u});
    return shown;
}
