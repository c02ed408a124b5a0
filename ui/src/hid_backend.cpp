// The real HidBackend: hidapi (its hidraw flavour on Linux).
#include "ui/space_mouse.h"

#include <hidapi/hidapi.h>

#include <cerrno>
#include <cstring>

namespace ui {

namespace {

std::string narrow(const wchar_t* text) {
    std::string out;
    for (; text && *text; ++text) out += *text < 128 ? char(*text) : '?';
    return out;
}

class Hidapi final : public HidBackend {
  public:
    Hidapi() : m_ready(hid_init() == 0) {}
    ~Hidapi() override {
        close();
        if (m_ready) hid_exit();
    }
    std::vector<Device> enumerate() override {
        std::vector<Device> found;
        if (!m_ready) return found;
        hid_device_info* all = hid_enumerate(0, 0);
        for (const hid_device_info* d = all; d; d = d->next)
            found.push_back({d->path ? d->path : "", narrow(d->product_string), d->vendor_id, d->product_id});
        hid_free_enumeration(all);
        return found;
    }
    bool open(const std::string& path, std::string& error) override {
        close();
        errno = 0;
        m_device = hid_open_path(path.c_str());
        if (!m_device) {
            error = errno != 0 ? std::strerror(errno) : narrow(hid_error(nullptr));
            return false;
        }
        hid_set_nonblocking(m_device, 1);
        return true;
    }
    int read(std::span<uint8_t> buffer) override {
        return m_device ? hid_read(m_device, buffer.data(), buffer.size()) : -1;
    }
    void close() override {
        if (m_device) hid_close(m_device);
        m_device = nullptr;
    }

  private:
    bool m_ready = false;
    hid_device* m_device = nullptr;
};

} // namespace

std::unique_ptr<HidBackend> makeHidapiBackend() { return std::make_unique<Hidapi>(); }

} // namespace ui
