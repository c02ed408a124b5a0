// Image stacks through OpenImageIO: a folder of 2D slices, a printf-style numbered pattern, or the
// pages of one multi-page TIFF. Every slice must match the first in size, channels (one: greyscale)
// and pixel type; the stack's z runs in slice-number order. Spacing is 1 (images carry none we trust).
#include "renderer/io/volume_io.h"

#include "volume_io_detail.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>

namespace renderer {
namespace {

using namespace io;

constexpr int kMaxSlices = 1 << 16;
// The most pixel bytes a slice file may claim per byte of file: above deflate's 1032:1 and LZW's
// ~1365:1 (table resets every 4094 codes). A 182-byte TIFF claiming 65535 x 65535 pixels would
// otherwise allocate gigabytes before OpenImageIO finds the data missing (found by fuzz_stack).
constexpr uintmax_t kMaxImageExpansion = 2048;

std::optional<VoxelType> voxelTypeOf(const OIIO::TypeDesc& t) {
    if (t == OIIO::TypeDesc::UINT8) return VoxelType::U8;
    if (t == OIIO::TypeDesc::UINT16) return VoxelType::U16;
    if (t == OIIO::TypeDesc::INT16) return VoxelType::I16;
    if (t == OIIO::TypeDesc::FLOAT) return VoxelType::F32;
    return std::nullopt;
}

bool isSliceFile(const fs::path& p) {
    const std::string ext = lower(p.extension().string());
    return ext == ".tif" || ext == ".tiff" || ext == ".png";
}

// The numbers in a name compared as numbers: slice2 < slice10.
bool naturalLess(const std::string& a, const std::string& b) {
    size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        if (std::isdigit(static_cast<unsigned char>(a[i])) &&
            std::isdigit(static_cast<unsigned char>(b[j]))) {
            size_t ie = i, je = j;
            while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie])))
                ++ie;
            while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je])))
                ++je;
            std::string_view na = std::string_view(a).substr(i, ie - i),
                             nb = std::string_view(b).substr(j, je - j);
            while (na.size() > 1 && na[0] == '0')
                na.remove_prefix(1);
            while (nb.size() > 1 && nb[0] == '0')
                nb.remove_prefix(1);
            if (na.size() != nb.size()) return na.size() < nb.size();
            if (na != nb) return na < nb;
            i = ie, j = je;
        } else {
            if (a[i] != b[j]) return a[i] < b[j];
            ++i, ++j;
        }
    }
    return a.size() - i < b.size() - j;
}

// The slice files a pattern such as "dir/slice_%03d.png" names, in number order. Numbers must be
// consecutive: a gap is a missing slice, not a thinner volume.
std::vector<fs::path> patternFiles(const fs::path& pattern) {
    const std::string name = pattern.filename().string();
    const size_t percent = name.find('%');
    size_t spec = percent + 1;
    while (spec < name.size() && std::isdigit(static_cast<unsigned char>(name[spec])))
        ++spec;
    if (spec >= name.size() || name[spec] != 'd' || name.find('%', spec) != std::string::npos)
        fail(pattern, "", "slice pattern must hold one %d (e.g. slice_%03d.png)");
    const std::string prefix = name.substr(0, percent), suffix = name.substr(spec + 1);
    const fs::path dir = pattern.has_parent_path() ? pattern.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) fail(pattern, "", "cannot open the folder '" + dir.string() + "'");
    std::vector<std::pair<long long, fs::path>> found;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string file = entry.path().filename().string();
        if (file.size() <= prefix.size() + suffix.size() || !file.starts_with(prefix) ||
            !file.ends_with(suffix))
            continue;
        const std::string_view digits =
            std::string_view(file).substr(prefix.size(), file.size() - prefix.size() - suffix.size());
        long long n = 0;
        const auto [end, errc] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
        if (errc == std::errc() && end == digits.data() + digits.size()) found.emplace_back(n, entry.path());
    }
    if (found.empty()) fail(pattern, "", "no file in '" + dir.string() + "' matches the slice pattern");
    std::sort(found.begin(), found.end());
    std::vector<fs::path> files;
    for (size_t i = 0; i < found.size(); ++i) {
        if (i > 0 && found[i].first != found[i - 1].first + 1)
            fail(pattern, "",
                 "slice " + std::to_string(found[i - 1].first + 1) + " is missing (found " +
                     std::to_string(found[i - 1].first) + " and " + std::to_string(found[i].first) + ")");
        files.push_back(found[i].second);
    }
    return files;
}

// Collects slices into a volume, checking each against the first.
struct StackBuilder {
    fs::path report;
    Volume volume;
    bool started = false;
    std::vector<std::vector<unsigned char>> slices;   // as stored, in this machine's byte order
    uintmax_t fileBytes = 0;    // size of every slice file opened so far
    uintmax_t claimedBytes = 0; // pixel bytes of every slice read so far

    void add(OIIO::ImageInput& in, const std::string& where) {
        const OIIO::ImageSpec& spec = in.spec();
        if (spec.nchannels != 1)
            fail(report, "channels",
                 where + " has " + std::to_string(spec.nchannels) +
                     " channels, expected 1 (greyscale slices)");
        if (spec.depth != 1)
            fail(report, "depth",
                 where + " is a " + std::to_string(spec.depth) + "-deep volume image, expected 2D slices");
        const auto type = voxelTypeOf(spec.format);
        if (!type)
            fail(report, "pixel type",
                 where + " is " + spec.format.c_str() + ", expected uint8, uint16, int16 or float");
        if (!started) {
            volume.name = volumeName(report);
            volume.type = *type;
            volume.dims = checkedDims(report, "width/height", spec.width, spec.height, 1);
            started = true;
        } else if (spec.width != volume.dims.x || spec.height != volume.dims.y || *type != volume.type) {
            fail(report, "slice size",
                 where + " is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " " +
                     voxelTypeName(*type) + ", expected " + std::to_string(volume.dims.x) + "x" +
                     std::to_string(volume.dims.y) + " " + voxelTypeName(volume.type) +
                     " like the first slice");
        }
        if (slices.size() >= size_t(kMaxSlices) ||
            (slices.size() + 1) * size_t(volume.dims.x) * size_t(volume.dims.y) > kMaxVoxels)
            fail(report, "slices",
                 "more than " + std::to_string(kMaxVoxels) + " voxels or " + std::to_string(kMaxSlices) +
                     " slices");
        const size_t count = size_t(volume.dims.x) * size_t(volume.dims.y);
        checkVoxelsFitTheBudget(report, "slices", std::to_string(slices.size() + 1) + " slices of " +
                                                      std::to_string(volume.dims.x) + " x " + std::to_string(volume.dims.y),
                                (slices.size() + 1) * count, volume.type);
        claimedBytes += count * voxelTypeBytes(volume.type);
        if (claimedBytes > fileBytes * kMaxImageExpansion + (uintmax_t(1) << 20))
            fail(report, "width/height",
                 where + " claims " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     " pixels: " + std::to_string(claimedBytes) +
                     " bytes of pixels so far cannot come from " + std::to_string(fileBytes) +
                     " bytes of image files");
        // Read in the stored type (OIIO would normalise integers to 0..1 if asked for float), which
        // the volume keeps: the values stay in the data's own units.
        std::vector<unsigned char>& stored = slices.emplace_back(count * voxelTypeBytes(volume.type));
        if (!in.read_image(in.current_subimage(), 0, 0, 1, spec.format, stored.data()))
            fail(report, "pixels", where + ": " + in.geterror());
    }

    Volume finish() {
        volume.dims.z = int(slices.size());
        // Each slice is freed once copied; the slices and the volume are both held only at the start.
        volume.values = VoxelValues::zeros(volume.type, volume.voxelCount());
        const size_t plane = size_t(volume.dims.x) * size_t(volume.dims.y);
        for (size_t k = 0; k < slices.size(); ++k) {
            decodeVoxels(slices[k].data(), plane, std::endian::native == std::endian::little ? Endian::Little : Endian::Big,
                         volume.values, k * plane);
            std::vector<unsigned char>().swap(slices[k]);
        }
        updateRange(volume);
        return std::move(volume);
    }
};

std::unique_ptr<OIIO::ImageInput> openImage(const fs::path& report, const fs::path& file,
                                            const std::string& where) {
    openFile(file, report, "slice").close(); // regular file, readable: the same checks as every format
    auto in = OIIO::ImageInput::open(file.string());
    if (!in) {
        std::string why = OIIO::geterror();
        if (why.empty()) why = "not an image OpenImageIO can read";
        fail(report, "slice", where + ": " + why);
    }
    return in;
}

} // namespace

Volume loadImageStack(const std::filesystem::path& pathOrPattern, const ProgressCallback& progress) {
    StackBuilder stack;
    stack.report = pathOrPattern;
    std::error_code ec;
    const std::string name = pathOrPattern.filename().string();

    // 1. One multi-page TIFF: each page (subimage) is a slice.
    if (name.find('%') == std::string::npos && !fs::is_directory(pathOrPattern, ec)) {
        auto in = openImage(pathOrPattern, pathOrPattern, "page 0");
        stack.fileBytes = fileSize(pathOrPattern, pathOrPattern, "");
        for (int page = 0;; ++page) {
            if (page > 0 && !in->seek_subimage(page, 0)) break;
            stack.add(*in, "page " + std::to_string(page));
        }
        return stack.finish();
    }

    // 2. A folder (every .tif/.tiff/.png in natural order) or a numbered pattern.
    std::vector<fs::path> files;
    if (name.find('%') != std::string::npos) {
        files = patternFiles(pathOrPattern);
    } else {
        for (const auto& entry : fs::directory_iterator(pathOrPattern, ec))
            if (isSliceFile(entry.path())) files.push_back(entry.path());
        if (files.empty()) fail(pathOrPattern, "", "folder holds no .tif, .tiff or .png slices");
        std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
            return naturalLess(a.filename().string(), b.filename().string());
        });
        // slice_1.png and slice_01.png hold the same number: which comes first is not known, and reading
        // both would put one slice in twice.
        for (size_t k = 1; k < files.size(); ++k)
            if (!naturalLess(files[k - 1].filename().string(), files[k].filename().string()))
                fail(pathOrPattern, "slices",
                     "'" + files[k - 1].filename().string() + "' and '" + files[k].filename().string() +
                         "' have the same number, expected one file per slice number (remove one of them)");
    }
    if (files.size() > size_t(kMaxSlices))
        fail(pathOrPattern, "slices",
             std::to_string(files.size()) + " files, more than " + std::to_string(kMaxSlices));
    for (size_t k = 0; k < files.size(); ++k) {
        const std::string where = "slice '" + files[k].filename().string() + "'";
        auto in = openImage(pathOrPattern, files[k], where);
        stack.fileBytes += fileSize(files[k], pathOrPattern, "slice");
        stack.add(*in, where);
        reportProgress(progress, double(k + 1) / double(files.size()), pathOrPattern);
    }
    return stack.finish();
}

} // namespace renderer
