// readJsonFile (json_file.h).
#include "renderer/io/json_file.h"

#include "renderer/errors.h"
#include "renderer/io/atomic_file.h"

#include <fstream>

namespace renderer {

nlohmann::json readJsonFile(const std::filesystem::path& path, const std::string& what) {
    requireRegularFile(path, what);   // a FIFO would block the read forever
    std::ifstream in(path);
    if (!in) throw LoadError(path.string(), "", "cannot open");
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw LoadError(path.string(), "", std::string("not valid JSON: ") + e.what());
    } catch (const std::exception& e) {   // the stream failed: a device, a read error
        throw LoadError(path.string(), "", std::string("cannot read: ") + e.what());
    }
}

} // namespace renderer
