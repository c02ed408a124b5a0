// A stand-in for OpenImageIO in the GPU bench bundle (scripts/gpu-bench --pack). The real library
// pulls in about 360 MB of codecs (OpenCV, GDAL, OpenVDB, ffmpeg), too much to carry to a GPU machine
// that has none of the Debian packages. SplatLab's bench and GL tests need no image files, so every
// entry point here fails the way OpenImageIO fails on an unknown format: no reader, no writer, and an
// error message that says why. Built against the installed OpenImageIO headers, so the symbols match.
#include <OpenImageIO/imageio.h>

#include <cstdlib>
#include <string>

OIIO_NAMESPACE_BEGIN

static const char* kWhy = "image files are not available in the GPU bench bundle (OpenImageIO stand-in)";

std::unique_ptr<ImageInput> ImageInput::open(const std::string&, const ImageSpec*, Filesystem::IOProxy*) {
    return nullptr;
}
std::unique_ptr<ImageOutput> ImageOutput::create(string_view, Filesystem::IOProxy*, string_view) {
    return nullptr;
}
std::string geterror(bool) { return kWhy; }
std::string ImageInput::geterror(bool) const { return kWhy; }
std::string ImageOutput::geterror(bool) const { return kWhy; }

// Reached only through an ImageInput or ImageOutput, which this library never returns.
ImageSpec::ImageSpec(int, int, int, TypeDesc) noexcept { std::abort(); }
void ParamValue::clear_value() noexcept {}
const char* TypeDesc::c_str() const { return "unknown"; }
size_t TypeDesc::basesize() const noexcept { return 0; }

OIIO_NAMESPACE_END
