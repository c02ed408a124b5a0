// replaceFileAtomically, writeFileAtomically (atomic_file.h).
#include "renderer/io/atomic_file.h"

#include "renderer/errors.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

namespace renderer {

void replaceFileAtomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& tmp)>& write) {
    const auto tmp = std::filesystem::path(path.string() + ".tmp");
    // Claim the temporary name first: a file or folder of that name that is not ours is left alone.
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0666);
    if (fd < 0)
        throw LoadError(path.string(), "",
                        errno == EEXIST ? "cannot write: '" + tmp.string() +
                                              "' is in the way (a file or folder of that name; move it and save again)"
                                        : "cannot write: " + std::string(std::strerror(errno)));
    ::close(fd);
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
