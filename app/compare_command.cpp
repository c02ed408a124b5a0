// `splatlab compare` (see compare_command.h).
#include "compare_command.h"

#include "renderer/errors.h"
#include "renderer/io/image.h"
#include "renderer/math/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

using namespace renderer;

namespace {

// A NaN or infinity in `image` would make every figure of the comparison NaN or inf.
void requireFinite(const Image& image, const std::string& path) {
    const auto bad = std::find_if(image.rgba.begin(), image.rgba.end(), [](float v) { return !std::isfinite(v); });
    if (bad == image.rgba.end()) return;
    const size_t pixel = size_t(bad - image.rgba.begin()) / 4;
    throw LoadError(path, "", "a pixel is not a finite number (at (" + std::to_string(pixel % size_t(image.width)) +
                                  ", " + std::to_string(pixel / size_t(image.width)) + ")): nothing to compare");
}

} // namespace

CLI::App* addCompareCommand(CLI::App& app, CompareArgs& args) {
    auto* compare = app.add_subcommand("compare", "Error of image A against reference B: RMSE, PSNR, SSIM, max");
    compare->add_option("image", args.image, "Image to judge (EXR keeps float data)")->required();
    compare->add_option("reference", args.reference, "Reference image")->required();
    compare->add_option("--diff", args.diff, "Write |A - B| x gain as an image");
    compare->add_option("--gain", args.gain, "Amplification of the difference image")->capture_default_str();
    return compare;
}

int runCompare(const CompareArgs& args) {
    const std::string &a = args.image, &b = args.reference, &diff = args.diff;
    const double gain = args.gain;
    if (!(gain > 0.0 && std::isfinite(gain))) throw CLI::ValidationError("--gain", "must be a finite number > 0");
    if (!diff.empty()) {
        for (const std::string& input : {a, b}) {
            std::error_code ec;
            if (std::filesystem::equivalent(diff, input, ec))
                throw CLI::ValidationError("--diff", "'" + diff + "' is an image being compared; name another file");
        }
        checkImageWritable(diff);
    }
    const Image image = readImage(a), reference = readImage(b);
    if (image.width != reference.width || image.height != reference.height)
        throw LoadError(a, "", std::to_string(image.width) + "x" + std::to_string(image.height) + " px, but " + b +
                                   " is " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                                   ": render both at one --size");
    requireFinite(image, a);
    requireFinite(reference, b);
    // .png holds the view composited over the background in 8 bits; .exr and .tif premultiplied float RGBA.
    if (isFloatImageFormat(a) != isFloatImageFormat(b))
        std::fprintf(stderr,
                     "note: one image is 8-bit composited over its background (.png), the other premultiplied "
                     "float RGBA: their alpha and colours differ by more than the renderers do; compare two of "
                     "one kind\n");
    const ImageError e = compareImages(image, reference);
    std::printf("%s vs %s: RMSE %.6f  PSNR %.2f dB  SSIM %.5f  max error %.6f at (%d, %d)\n", a.c_str(), b.c_str(),
                e.rmse, e.psnrDb, e.ssim, e.maxAbs, e.maxX, e.maxY);
    if (!diff.empty()) writeImage(differenceImage(image, reference, gain), diff);
    return 0;
}

