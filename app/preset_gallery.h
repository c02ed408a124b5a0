// The Transfer function panel's gallery: a thumbnail of each preset drawn on the volume shown. They are
// rendered on the render thread, one task each (views asked meanwhile go between them), and kept until the
// volume or its window changes. The panel draws them (ui::GalleryThumbnail); the editor decides when.
#pragma once
#include "render_thread.h"
#include "view_texture.h"

#include "renderer/model/transfer_function.h"

#include <array>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ui {
struct GalleryThumbnail;
}

constexpr int kThumbnailPx = 96;                 // each thumbnail is this many pixels square
constexpr size_t kThumbnailMaxVoxels = 2u << 20; // drawn from the finest level with at most this many

// What thumbnails are drawn from: the scene on one of the render thread's renderers.
struct ThumbnailSource {
    int level = 0;                    // 0: the full scene's renderer; k: the level at 1/2^k per axis
    renderer::ValueRange window;      // that scene's window: the presets' LUTs are baked over it
    renderer::ImagePlane plane;       // thumbnailPlane()
    renderer::SplatSettings settings; // that renderer's settings for the view (no heatmap)
    renderer::TfTables shownTables;   // the view's LUT and gradient factors there, put back after each thumbnail
};

// A kThumbnailPx square view of the scene: the default camera's direction about `up`, the scene framed.
renderer::ImagePlane thumbnailPlane(const renderer::SplatScene& scene, const glm::dvec3& up);
// A preset as the gallery draws and applies it: in data units over `window` (as the Preset combo does).
renderer::TransferFunction galleryPreset(const std::string& name, renderer::ValueRange window);
// One preset's thumbnail on the render thread: `tf`'s LUT on the source's renderer, a frame, its read-back,
// then the view's LUT back. The future throws what the render threw.
std::future<renderer::Image> renderThumbnail(RenderThread& thread, const ThumbnailSource& source,
                                             const renderer::TransferFunction& tf);
// The image over `background` in 8 bits, as the viewport shows its own: rgb + (1 - a) background.
std::vector<uint8_t> overBackground(const renderer::Image& image, const std::array<float, 3>& background);

// The thumbnails of the presets, in builtinPresetNames() order, and the one being drawn.
class PresetGallery {
  public:
    // Every thumbnail forgotten (the volume or the window changed); one in flight is dropped when done.
    void invalidate();
    // A finished thumbnail into its texture (the UI's context must be current); then, with none in flight,
    // the next missing one started from `source`. `wait`: scripted runs wait for it (deterministic frames).
    // Returns true when a thumbnail arrived.
    bool step(RenderThread& thread, const ThumbnailSource& source, const std::array<float, 3>& background,
              bool wait);
    bool complete() const;                                 // every preset has its thumbnail
    bool drawing() const { return m_pending.has_value(); } // a thumbnail is in flight
    std::vector<ui::GalleryThumbnail> thumbnails() const;

  private:
    struct Entry {
        std::string name;
        std::unique_ptr<ViewTexture> texture; // null until drawn
        bool failed = false;                  // its render threw: not tried again for this volume
    };
    std::vector<Entry> m_entries;
    struct Pending {
        size_t entry = 0;
        uint64_t generation = 0; // invalidate() since: its image is of an older volume or window
        std::future<renderer::Image> image;
    };
    std::optional<Pending> m_pending;
    uint64_t m_generation = 0;
};
