// 3D mice: device ids, reports, motion and the polling loop (space_mouse.h).
#include "ui/space_mouse.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ui {

bool isSpaceMouse(uint16_t vendor, uint16_t product) {
    // Logitech-era: SpaceMouse Plus XT, CADman, SpaceMouse Classic, SpaceBall 5000, SpaceTraveler,
    // SpacePilot, SpaceNavigator, SpaceExplorer, SpaceNavigator for Notebooks, SpacePilot Pro,
    // SpaceMouse Pro.
    static constexpr uint16_t kLogitech[] = {0xc603, 0xc605, 0xc606, 0xc621, 0xc623, 0xc625,
                                             0xc626, 0xc627, 0xc628, 0xc629, 0xc62b};
    // 3Dconnexion's own: SpaceMouse Wireless (cable, receiver), Pro Wireless (cable, receiver),
    // Enterprise, Compact, Module, Wireless over Bluetooth, the Universal Receiver.
    static constexpr uint16_t k3Dconnexion[] = {0xc62e, 0xc62f, 0xc631, 0xc632, 0xc633,
                                                0xc635, 0xc636, 0xc63a, 0xc652};
    auto in = [product](std::span<const uint16_t> ids) { return std::ranges::find(ids, product) != ids.end(); };
    return (vendor == 0x046d && in(kLogitech)) || (vendor == 0x256f && in(k3Dconnexion));
}

namespace {

int int16At(std::span<const uint8_t> r, size_t i) { return int16_t(uint16_t(r[i] | r[i + 1] << 8)); }

void readAxes(std::array<int, 3>& axes, std::span<const uint8_t> r, size_t first) {
    for (size_t a = 0; a < 3; ++a) axes[a] = int16At(r, first + 2 * a);
}

// Deflection as a fraction of full travel, zero inside the dead zone and continuous at its edge.
double deflection(int raw) {
    const double t = std::abs(double(raw)) / kSpaceMouseFullScale;
    const double beyond = std::max(t - kSpaceMouseDeadZone, 0.0) / (1.0 - kSpaceMouseDeadZone);
    return std::copysign(std::min(beyond, 1.5), double(raw));   // devices overshoot 350 a little
}

} // namespace

bool SpaceMouseState::deflected() const {
    for (int a = 0; a < 3; ++a)
        if (deflection(translation[size_t(a)]) != 0.0) return true;
    return deflection(rotation[0]) != 0.0 || deflection(rotation[2]) != 0.0;   // roll (about y) moves nothing
}

bool applySpaceMouseReport(SpaceMouseState& state, std::span<const uint8_t> report) {
    if (report.empty()) return false;
    switch (report[0]) {
    case 1:
        if (report.size() < 7) return false;
        readAxes(state.translation, report, 1);
        if (report.size() >= 13) readAxes(state.rotation, report, 7);   // one report for all six axes
        return true;
    case 2:
        if (report.size() < 7) return false;
        readAxes(state.rotation, report, 1);
        return true;
    case 3: {
        if (report.size() < 2) return false;
        uint32_t buttons = 0;
        for (size_t i = 1; i < std::min<size_t>(report.size(), 5); ++i) buttons |= uint32_t(report[i]) << (8 * (i - 1));
        state.buttons = buttons;
        return true;
    }
    default: return false;
    }
}

OrbitInput spaceMouseOrbit(const SpaceMouseState& state, double dtSeconds, const SpaceMouseMapping& mapping) {
    OrbitInput input;
    const double dt = std::clamp(dtSeconds, 0.0, kSpaceMouseMaxStepSec) * mapping.speed;
    if (!(dt > 0.0)) return input;
    const double turn = mapping.invertRotation ? -1.0 : 1.0, move = mapping.invertTranslation ? -1.0 : 1.0;
    // Twist clockwise seen from above (+z is down) turns the object clockwise: the azimuth decreases.
    const double azimuthDeg = -turn * deflection(state.rotation[2]) * kSpaceMouseDegPerSec * dt;
    // Tilt the knob's top away from the user (about +x): the object tips away, the view rises.
    const double elevationDeg = turn * deflection(state.rotation[0]) * kSpaceMouseDegPerSec * dt;
    input.rotateDxPx = float(-azimuthDeg / kOrbitDegPerPx);   // applyOrbitInput's gains, undone
    input.rotateDyPx = float(elevationDeg / kOrbitDegPerPx);
    // Push away from the user (-y) brings the object closer.
    const double factor = std::pow(kSpaceMouseZoomPerSec, -move * deflection(state.translation[1]) * dt);
    input.wheelNotches = float(std::log(factor) / std::log(kZoomPerNotch));
    input.panDxPx = float(move * deflection(state.translation[0]) * kSpaceMousePanPxPerSec * dt);
    input.panDyPx = float(move * deflection(state.translation[2]) * kSpaceMousePanPxPerSec * dt);
    return input;
}

SpaceMouse::SpaceMouse(std::unique_ptr<HidBackend> backend) : m_backend(std::move(backend)) {}

SpaceMouse::~SpaceMouse() {
    if (m_connected) m_backend->close();
}

void SpaceMouse::scan(double nowSeconds) {
    m_lastScan = nowSeconds;
    std::string refused;   // the last device that would not open, and why
    for (const HidBackend::Device& d : m_backend->enumerate()) {
        if (!isSpaceMouse(d.vendor, d.productId)) continue;
        char ids[16];
        std::snprintf(ids, sizeof ids, "%04x:%04x", d.vendor, d.productId);
        const std::string name = (d.product.empty() ? std::string("3D mouse") : d.product) + " (" + ids + ")";
        std::string error;
        if (m_backend->open(d.path, error)) {
            m_connected = true;
            m_state = {};
            m_status = name;
            return;
        }
        refused = name + " found, but " + d.path + " cannot be opened: " + error +
                  " (docs/editor.md gives the udev rule that lets users read it)";
    }
    m_status = refused.empty() ? "no 3D mouse found" : refused;
}

void SpaceMouse::poll(double nowSeconds) {
    if (!m_connected) {
        if (nowSeconds - m_lastScan >= kRescanSeconds) scan(nowSeconds);
        if (!m_connected) return;
    }
    std::array<uint8_t, 64> buffer{};
    for (int i = 0; i < kMaxReportsPerPoll; ++i) {
        const int n = m_backend->read(buffer);
        if (n == 0) return;
        if (n < 0) {   // unplugged: stop moving, look again later
            m_backend->close();
            m_connected = false;
            m_state = {};
            m_status = "3D mouse disconnected";
            m_lastScan = nowSeconds;
            return;
        }
        applySpaceMouseReport(m_state, std::span<const uint8_t>(buffer.data(), size_t(std::min<int>(n, 64))));
    }
}

} // namespace ui
