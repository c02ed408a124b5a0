// The ground-truth cache's budget and its pruning (ground_truth_cache.h).
#include "renderer/oracle/ground_truth_cache.h"

#include "renderer/errors.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <string>
#include <system_error>
#include <vector>

namespace renderer {

uint64_t groundTruthCacheBudgetBytes() {
    const char* text = std::getenv("SPLATLAB_CACHE_MAX_MB");
    if (!text || !*text) return kDefaultCacheBudgetMiB << 20;
    char* end = nullptr;
    errno = 0;
    const unsigned long long mib = std::strtoull(text, &end, 10);
    // At most 2^40 MiB, so the bytes fit 64 bits; a sign, a fraction or a unit is refused.
    if (*end != '\0' || errno != 0 || mib < 1 || mib > (1ull << 40) || !(text[0] >= '0' && text[0] <= '9'))
        throw RenderError("SPLATLAB_CACHE_MAX_MB='" + std::string(text) +
                          "': expected the ground-truth cache's size as a whole number of MiB, 1 or more");
    return uint64_t(mib) << 20;
}

uint64_t pruneGroundTruthCache(const std::filesystem::path& dir, uint64_t maxBytes,
                               const std::filesystem::path& keep) {
    struct Entry {
        std::filesystem::path path;
        std::filesystem::file_time_type used;
        uint64_t bytes;
    };
    std::vector<Entry> entries;
    uint64_t total = 0;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code fileEc;
        if (it->path().extension() != ".exr" || !it->is_regular_file(fileEc)) continue;
        const uint64_t bytes = it->file_size(fileEc);
        if (fileEc) continue;
        const auto used = it->last_write_time(fileEc);
        if (fileEc) continue;
        total += bytes;
        if (!std::filesystem::equivalent(it->path(), keep, fileEc)) entries.push_back({it->path(), used, bytes});
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
    uint64_t removed = 0;
    for (const Entry& e : entries) {
        if (total <= maxBytes) break;
        std::error_code removeEc;
        if (!std::filesystem::remove(e.path, removeEc) || removeEc) continue;
        total -= e.bytes;
        removed += e.bytes;
    }
    return removed;
}

} // namespace renderer
