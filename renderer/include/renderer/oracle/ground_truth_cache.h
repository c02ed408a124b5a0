// The ground-truth cache keeps the references used last within a budget of bytes. A reference costs
// seconds to minutes to trace, so it is kept on disk; but the editor's split view makes one per view the
// camera rests at, so a cache nobody pruned grew without end.
#pragma once
#include <cstdint>
#include <filesystem>

namespace renderer {

// The budget: $SPLATLAB_CACHE_MAX_MB (a whole number of MiB, 1 or more), else kDefaultCacheBudgetMiB.
// Throws RenderError naming the variable and what was expected when it holds anything else.
constexpr uint64_t kDefaultCacheBudgetMiB = 1024;
uint64_t groundTruthCacheBudgetBytes();

// Removes the least recently used references (the *.exr files directly in `dir`, oldest modification
// time first; a cache hit renews it) until the rest take at most `maxBytes`; `keep` (the entry just
// written) is never removed. Best effort: a file that cannot be read or removed (another process took
// it) is skipped. Returns the bytes removed.
uint64_t pruneGroundTruthCache(const std::filesystem::path& dir, uint64_t maxBytes,
                               const std::filesystem::path& keep);

} // namespace renderer
