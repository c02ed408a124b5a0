// 3Dconnexion-class 3D mice (SpaceNavigator, SpaceMouse, SpacePilot...) read through hidapi: which
// devices are ones, what their HID reports say, and the camera motion they ask for. The knob works
// like a joystick: its deflection is a speed, so the camera moves by deflection x rate x frame time.
// The report parsing and the motion are pure functions; SpaceMouse does the device I/O through a
// HidBackend, which tests replace with a fake.
#pragma once
#include "ui/panels.h"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace ui {

// The knob's deflection as the device reports it (about -350..350 at full travel), in HID axes:
// x right, y towards the user, z down; rotations about those axes.
struct SpaceMouseState {
    std::array<int, 3> translation{}, rotation{};
    uint32_t buttons = 0;   // bit i: button i held
    // Any axis the camera follows (all but roll) past the dead zone: the knob asks for motion.
    bool deflected() const;
};

// 3Dconnexion's six-axis products, under Logitech's vendor id (older ones) and 3Dconnexion's own.
bool isSpaceMouse(uint16_t vendor, uint16_t product);

// Applies one input report (report id first) to `state`. Report 1: translation (newer devices add the
// rotation in the same report), 2: rotation, 3: buttons. Returns false, leaving `state` alone, for
// a report too short for its id or of another id (LEDs, battery).
bool applySpaceMouseReport(SpaceMouseState& state, std::span<const uint8_t> report);

constexpr double kSpaceMouseFullScale = 350.0;    // deflection at full travel
constexpr double kSpaceMouseDeadZone = 0.05;      // of full scale: the knob never rests exactly at 0
constexpr double kSpaceMouseDegPerSec = 120.0;    // orbit at full twist or tilt, speed 1
constexpr double kSpaceMouseZoomPerSec = 0.5;     // distance factor a second at full push, speed 1
constexpr double kSpaceMousePanPxPerSec = 600.0;  // pan at full slide, speed 1
constexpr double kSpaceMouseMaxStepSec = 0.1;     // a stalled frame moves the camera no further than this

// The orbit input `dtSeconds` of `state` ask for (applyOrbitInput() then applies the one camera rule):
// twist (about z) turns the azimuth, tilt forward or back (about x) the elevation, push or pull (y)
// zooms in or out, slide (x) and lift (z) pan. Roll (about y) is unused: the orbit camera has none.
// mapping.enabled is the caller's to check.
OrbitInput spaceMouseOrbit(const SpaceMouseState& state, double dtSeconds, const SpaceMouseMapping& mapping);

// What SpaceMouse needs from HID. makeHidapiBackend() is the real one.
class HidBackend {
  public:
    struct Device {
        std::string path, product;
        uint16_t vendor = 0, productId = 0;
    };
    virtual ~HidBackend() = default;
    virtual std::vector<Device> enumerate() = 0;
    // Opens `path` for non-blocking reads; on failure returns false and says why in `error`.
    virtual bool open(const std::string& path, std::string& error) = 0;
    // One waiting report into `buffer`: its length, 0 when none is waiting, -1 when the device is gone.
    virtual int read(std::span<uint8_t> buffer) = 0;
    virtual void close() = 0;
};
std::unique_ptr<HidBackend> makeHidapiBackend();

// The first 3D mouse found, kept open, its reports read without blocking. While none is open it looks
// again every kRescanSeconds (plugged in later, or unplugged and back).
class SpaceMouse {
  public:
    static constexpr double kRescanSeconds = 2.0;
    static constexpr int kMaxReportsPerPoll = 256;   // a flood of reports cannot hold up a frame

    explicit SpaceMouse(std::unique_ptr<HidBackend> backend);
    ~SpaceMouse();
    // Reads the reports waiting; `nowSeconds` paces the rescans.
    void poll(double nowSeconds);
    bool connected() const { return m_connected; }
    const SpaceMouseState& state() const { return m_state; }
    // For the Settings panel: the device and its ids, or why there is none.
    const std::string& status() const { return m_status; }

  private:
    void scan(double nowSeconds);

    std::unique_ptr<HidBackend> m_backend;
    SpaceMouseState m_state;
    bool m_connected = false;
    double m_lastScan = -1e300;
    std::string m_status = "not looked for yet";
};

} // namespace ui
