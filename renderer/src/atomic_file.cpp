// writeFileAtomically (atomic_file.h).
#include "renderer/atomic_file.h"

#include "renderer/errors.h"

#include <fstream>
#include <system_error>

namespace renderer {

void writeFileAtomically(const std::filesystem::path& path, const std::string& text) {
    const auto tmp = std::filesystem::path(path.string() + ".tmp");
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    std::error_code ec;
    if (!out) {
        std::filesystem::remove(tmp, ec);
        throw LoadError(path.string(), "", "cannot write (" + tmp.string() + ")");
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        const std::string reason = "cannot replace: " + ec.message();
        std::filesystem::remove(tmp, ec);
        throw LoadError(path.string(), "", reason);
    }
}

} // namespace renderer
