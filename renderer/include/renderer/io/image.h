// A float RGBA image (premultiplied, row 0 at the top) and its comparisons; writing goes through
// OpenImageIO (PNG for people, EXR for float data).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace renderer {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgba;   // 4 floats a pixel, premultiplied alpha, row-major from the top

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgba(size_t(w) * size_t(h) * 4, 0.0f) {}
    float* pixel(int x, int y) { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
    const float* pixel(int x, int y) const { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
};

// Whether writeImage keeps `path`'s pixels as float premultiplied RGBA (.exr, .hdr, .tif, .tiff, .pfm)
// rather than compositing them over a background in 8 bits (.png and the rest).
bool isFloatImageFormat(const std::filesystem::path& path);
// PNG/JPEG etc.: composited over `background` (linear RGB), 8-bit. EXR/HDR/TIFF float: raw RGBA.
void writeImage(const Image& image, const std::filesystem::path& path, const float background[3] = nullptr);
Image readImage(const std::filesystem::path& path);
// Throws the LoadError writeImage(path) would for a folder, a missing folder or an unknown extension,
// so a long render can fail before it starts.
void checkImageWritable(const std::filesystem::path& path);

struct ImageStats {
    double meanAlpha = 0.0, maxAlpha = 0.0;
    double meanLuminance = 0.0;      // of premultiplied rgb
    double coveredFraction = 0.0;    // pixels with alpha > 1/255
    bool finite = true;              // no NaN or Inf anywhere
};
ImageStats imageStats(const Image& image);

} // namespace renderer
