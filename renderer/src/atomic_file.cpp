// replaceFileAtomically, writeFileAtomically (atomic_file.h).
#include "renderer/atomic_file.h"

#include "renderer/errors.h"

#include <fstream>
#include <system_error>

namespace renderer {

void replaceFileAtomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& tmp)>& write) {
    const auto tmp = std::filesystem::path(path.string() + ".tmp");
    std::error_code ec;
    try {
        write(tmp);
    } catch (...) {
        std::filesystem::remove(tmp, ec);
        throw;
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        const std::string reason = "cannot replace: " + ec.message();
        std::filesystem::remove(tmp, ec);
        throw LoadError(path.string(), "", reason);
    }
}

void writeFileAtomically(const std::filesystem::path& path, const std::string& text) {
    replaceFileAtomically(path, [&](const std::filesystem::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.close();
        if (!out) throw LoadError(path.string(), "", "cannot write (" + tmp.string() + ")");
    });
}

} // namespace renderer
