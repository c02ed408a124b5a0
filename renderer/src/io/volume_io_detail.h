// What the volume readers share (private to the renderer): error helpers, text parsing, size checks and
// the streamed voxel reader with raw, gzip/zlib and bzip2 storage. Each format lives in its own file
// (volume_io*.cpp); none of them allocates before the sizes were checked.
#pragma once
#include "renderer/errors.h"
#include "renderer/io/volume_io.h"

#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace renderer::io {

namespace fs = std::filesystem;

[[noreturn]] inline void fail(const fs::path& path, const std::string& field, const std::string& reason) {
    throw LoadError(path.string(), field, reason);
}

std::string lower(std::string_view s);
std::string_view trim(std::string_view s);
std::vector<std::string_view> splitWords(std::string_view s);
// Quotes text read from a file for an error message: binary junk becomes '?', long text is cut.
std::string excerpt(std::string_view s);
std::optional<long long> parseInt(std::string_view s);
std::optional<double> parseDouble(std::string_view s);
// "%g" of a double for messages (std::to_string prints 6 fixed decimals).
std::string number(double v);
std::string layoutText(glm::ivec3 dims, VoxelType type);

// Three axis sizes, each positive and fitting an int, product within kMaxVoxels; checked before any
// allocation so lying headers cannot overflow size_t (readVoxels then checks the memory budget).
glm::ivec3 checkedDims(const fs::path& path, const std::string& field, long long x, long long y, long long z);
// Refuses `voxels` of `type` (as the header `claim`s them) where they exceed volumeMemoryBudget().
void checkVoxelsFitTheBudget(const fs::path& path, const std::string& field, const std::string& claim,
                             uint64_t voxels, VoxelType type);
constexpr uint64_t kMiB = uint64_t(1) << 20;
// Each component finite and within [kMinSpacing, kMaxSpacing].
constexpr double kMinSpacing = 1e-6, kMaxSpacing = 1e6;
glm::dvec3 checkedSpacing(const fs::path& path, const std::string& field, glm::dvec3 spacing);

// The name shown for a volume: the file name without .gz/.bz2 and then the format's extension.
std::string volumeName(const fs::path& path);
// Opens a regular file for binary reading; directories, devices and FIFOs are refused (a FIFO would
// block the editor forever). `report` is the file named in the error, `field` the header field.
std::ifstream openFile(const fs::path& file, const fs::path& report, const std::string& field);
// Size of a regular file, or a LoadError.
uintmax_t fileSize(const fs::path& file, const fs::path& report, const std::string& field);

enum class Compression {
    None,
    Zlib,  // gzip or zlib wrapper, told apart by zlib from the stream's first bytes
    Bzip2, // only when built with libbz2 (bzip2Available())
};
bool bzip2Available();
const char* compressionName(Compression c); // "raw", "gzip/zlib", "bzip2"

// Sequential bytes of a stored stream from the current position of `in`, decompressed on the fly.
class ByteReader {
  public:
    ByteReader(std::istream& in, Compression compression, fs::path report);
    ~ByteReader();
    ByteReader(const ByteReader&) = delete;
    ByteReader& operator=(const ByteReader&) = delete;
    // Fills dst with n bytes; fewer only when the file (or the compressed stream) ended first.
    size_t read(unsigned char* dst, size_t n);

  private:
    struct State;
    std::istream& m_in;
    Compression m_compression;
    fs::path m_report;
    std::unique_ptr<State> m_state;
};

// Stored bytes of `count` voxels in `endian` order into out[first..first + count), which has the stored type.
void decodeVoxels(const unsigned char* bytes, size_t count, Endian endian, VoxelValues& out, size_t first);

// Where the voxel bytes are and how they are stored.
struct DataSource {
    fs::path file;             // the file holding the bytes (the header itself when attached)
    std::streamoff offset = 0; // where the stored (possibly compressed) data starts in `file`
    size_t lineSkip = 0;       // text lines to skip from `offset` before the data (NRRD "line skip")
    size_t byteSkip = 0;       // bytes to drop before the voxels, counted after decompression
    Compression compression = Compression::None;
    bool exact = false; // trailing bytes are an error (raw files) instead of being ignored (NRRD)
    Endian endian = Endian::Little;
    std::string sizeField = "sizes"; // the header field the sizes came from, named where they are over budget
    ProgressCallback progress; // the fraction of the voxels read, every chunk; false: throw Cancelled
};

// Tells `progress` (if any) the fraction done; throws Cancelled naming `report` when it says stop.
void reportProgress(const ProgressCallback& progress, double fraction, const fs::path& report);

// Reads dims/type voxels from `src`, kept in their type. `report` is the file named in errors.
VoxelValues readVoxels(const fs::path& report, const DataSource& src, glm::ivec3 dims, VoxelType type);

// Reads a whole (small) file into memory, refusing more than `maxBytes`.
std::string readSmallFile(const fs::path& path, size_t maxBytes);

} // namespace renderer::io
