// Image I/O through OpenImageIO and image statistics.
#include "renderer/io/image.h"

#include "renderer/io/atomic_file.h"
#include "renderer/errors.h"
#include "renderer/out_of_memory.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <vector>

namespace renderer {

bool isFloatImageFormat(const std::filesystem::path& path) {
    auto ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext == ".exr" || ext == ".hdr" || ext == ".tif" || ext == ".tiff" || ext == ".pfm";
}

// Writes `image` into `file` with the writer chosen for `path` (the name errors give).
static void writePixels(OIIO::ImageOutput& out, const Image& image, const std::filesystem::path& file,
                        const std::filesystem::path& path, const float background[3]) {
    const size_t n = size_t(image.width) * size_t(image.height);
    bool ok;
    if (isFloatImageFormat(path)) {
        OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
        ok = out.open(file.string(), spec) && out.write_image(OIIO::TypeDesc::FLOAT, image.rgba.data());
    } else {
        // For people: composite the premultiplied image over the background, 8-bit RGB.
        const float zero[3] = {0, 0, 0};
        const float* bg = background ? background : zero;
        std::vector<unsigned char> rgb =
            namingAllocation(path.string(), "8-bit copy of the image", n * 3,
                             " at " + std::to_string(image.width) + "x" + std::to_string(image.height),
                             [&] { return std::vector<unsigned char>(n * 3); });
        for (size_t i = 0; i < n; ++i) {
            const float* p = &image.rgba[i * 4];
            for (int c = 0; c < 3; ++c) {
                const float v = p[c] + (1.0f - p[3]) * bg[c];
                rgb[i * 3 + c] = (unsigned char)std::lround(std::clamp(std::isfinite(v) ? v : 0.f, 0.f, 1.f) * 255.f);
            }
        }
        OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
        ok = out.open(file.string(), spec) && out.write_image(OIIO::TypeDesc::UINT8, rgb.data());
    }
    if (!ok || !out.close()) throw LoadError(path.string(), "", "cannot write image: " + out.geterror());
}

enum class IsPng { No, Complete, Truncated };

// Whether `file` is a PNG (by its signature), and if so whether it ends in its IEND chunk.
static IsPng endsLikeAPng(const std::filesystem::path& file) {
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
    std::ifstream in(file, std::ios::binary);
    unsigned char head[8] = {}, tail[12] = {};
    if (!in.read(reinterpret_cast<char*>(head), 8) || !std::equal(head, head + 8, signature)) return IsPng::No;
    in.seekg(-12, std::ios::end);
    const bool ended = bool(in.read(reinterpret_cast<char*>(tail), 12)) && std::equal(tail, tail + 12, iend);
    return ended ? IsPng::Complete : IsPng::Truncated;
}

// Headers can claim any size: a 74-byte PNG may say 60000x60000. Reading holds the pixels twice as floats
// (the file's channels, then RGBA), so a claim is checked before anything is allocated: against half the
// machine's memory, and for PNG against what its file can hold (deflate expands at most 1032:1).
static void checkImageSize(const std::filesystem::path& path, const OIIO::ImageSpec& spec, const std::string& format) {
    const std::string claim = std::to_string(spec.width) + "x" + std::to_string(spec.height) + " pixels of " +
                              std::to_string(spec.nchannels) + " channels";
    if (spec.width < 1 || spec.height < 1 || spec.nchannels > 64)
        throw LoadError(path.string(), "size", "the header claims " + claim + "; expected at least 1x1, at most 64 channels");
    const double pixels = double(spec.width) * double(spec.height);
    const double needed = pixels * double(spec.nchannels + 4) * sizeof(float);
    const double budget = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE)) / 2.0;
    if (needed > budget)
        throw LoadError(path.string(), "size",
                        "the header claims " + claim + ": reading it needs " + std::to_string(int64_t(needed / (1 << 20))) +
                            " MiB, more than half this machine's memory (" + std::to_string(int64_t(budget / (1 << 20))) +
                            " MiB)");
    std::error_code ec;
    const double fileBytes = double(std::filesystem::file_size(path, ec));
    const double decodedBytes = pixels * spec.nchannels * double(spec.format.size()) + double(spec.height);
    if (!ec && format == "png" && decodedBytes > 1032.0 * fileBytes + (1 << 20))
        throw LoadError(path.string(), "size",
                        "the header claims " + claim + ", more than a PNG of " + std::to_string(int64_t(fileBytes)) +
                            " bytes can hold (deflate expands at most 1032:1): the file is damaged");
}

// The writer for `path`'s extension, after the checks a write would otherwise fail late on.
static std::unique_ptr<OIIO::ImageOutput> imageWriter(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw LoadError(path.string(), "", "is a folder; name an image file in it (.png, .exr, .tif)");
    const auto folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    if (!std::filesystem::is_directory(folder, ec))
        throw LoadError(path.string(), "", "cannot write: the folder '" + folder.string() + "' does not exist");
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out)
        throw LoadError(path.string(), "",
                        "no image writer for the extension '" + path.extension().string() +
                            "' (expected .png, .exr, .tif or another OpenImageIO format)");
    return out;
}

void checkImageWritable(const std::filesystem::path& path) {
    imageWriter(path);
    checkFileReplaceable(path);
}

void writeImage(const Image& image, const std::filesystem::path& path, const float background[3]) {
    // The writer is chosen by `path`'s extension and fills a temporary file that replaces `path` whole.
    auto out = imageWriter(path);
    replaceFileAtomically(path, [&](const std::filesystem::path& tmp) {
        writePixels(*out, image, tmp, path, background);
        // Some writers (PNG) do not report a write the disk refused: read the file back before it replaces
        // the old one. A PNG must end in its IEND chunk; that is checked first, since libpng's error exit
        // on a truncated file leaks in OpenImageIO 2.4.
        auto in = endsLikeAPng(tmp) != IsPng::Truncated ? OIIO::ImageInput::open(tmp.string()) : nullptr;
        std::vector<float> pixels;
        bool ok = in && in->spec().width == image.width && in->spec().height == image.height;
        if (ok) {
            const size_t floats = size_t(image.width) * size_t(image.height) * size_t(in->spec().nchannels);
            namingAllocation(path.string(), "image read back to check the write", floats * sizeof(float),
                             " at " + std::to_string(image.width) + "x" + std::to_string(image.height),
                             [&] { pixels.resize(floats); });
            ok = in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::FLOAT, pixels.data());
        }
        if (!ok)
            throw LoadError(path.string(), "",
                            std::string("cannot write image: what was written does not read back (is the disk full?)") +
                                ": " + (in ? in->geterror() : OIIO::geterror()));
    });
}

Image readImage(const std::filesystem::path& path) {
    requireRegularFile(path, "an image file");
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw LoadError(path.string(), "", "cannot read image: " + OIIO::geterror());
    const auto& spec = in->spec();
    if (spec.nchannels < 1) throw LoadError(path.string(), "channels", "image has no channels");
    checkImageSize(path, spec, in->format_name());
    // The file's channels as floats, then the RGBA image: named with their size should they not fit.
    const size_t pixels = size_t(spec.width) * size_t(spec.height);
    std::vector<float> data;
    Image img =
        namingAllocation(path.string(), "image's pixels", pixels * (size_t(spec.nchannels) + 4) * 4,
                         " at " + std::to_string(spec.width) + "x" + std::to_string(spec.height), [&] {
                             data.resize(pixels * size_t(spec.nchannels));
                             return Image(spec.width, spec.height);
                         });
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
        throw LoadError(path.string(), "", "cannot read pixels: " + in->geterror());
    for (size_t i = 0; i < size_t(spec.width) * spec.height; ++i) {
        const float* s = &data[i * spec.nchannels];
        float* d = &img.rgba[i * 4];
        for (int c = 0; c < 3; ++c) d[c] = s[std::min(c, spec.nchannels - 1)];
        d[3] = spec.nchannels >= 4 ? s[3] : 1.0f;
    }
    return img;
}

ImageStats imageStats(const Image& image) {
    ImageStats s;
    const size_t n = size_t(image.width) * size_t(image.height);
    if (n == 0) return s;
    size_t covered = 0;
    for (size_t i = 0; i < n; ++i) {
        const float* p = &image.rgba[i * 4];
        for (int c = 0; c < 4; ++c) s.finite = s.finite && std::isfinite(p[c]);
        s.meanAlpha += p[3];
        s.maxAlpha = std::max(s.maxAlpha, double(p[3]));
        s.meanLuminance += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        covered += p[3] > 1.0f / 255.0f;
    }
    s.meanAlpha /= double(n);
    s.meanLuminance /= double(n);
    s.coveredFraction = double(covered) / double(n);
    return s;
}

} // namespace renderer
