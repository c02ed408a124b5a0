// 3D mice: which devices count, what their reports say, the camera motion they ask for, and the
// polling loop (hot-plug, unplug, permissions) against a fake HID backend.
#include "ui/space_mouse.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <random>

namespace {

using testing::HasSubstr;
using ui::SpaceMouseState;

std::vector<uint8_t> axesReport(uint8_t id, std::array<int16_t, 3> v) {
    std::vector<uint8_t> r{id};
    for (int16_t x : v) r.push_back(uint8_t(uint16_t(x) & 0xff)), r.push_back(uint8_t(uint16_t(x) >> 8));
    return r;
}

} // namespace

TEST(SpaceMouseDevices, ThreeDconnexionProductsCountAndOtherDevicesDoNot) {
    EXPECT_TRUE(ui::isSpaceMouse(0x046d, 0xc626));    // SpaceNavigator
    EXPECT_TRUE(ui::isSpaceMouse(0x046d, 0xc62b));    // SpaceMouse Pro
    EXPECT_TRUE(ui::isSpaceMouse(0x256f, 0xc635));    // SpaceMouse Compact
    EXPECT_TRUE(ui::isSpaceMouse(0x256f, 0xc652));    // Universal Receiver
    EXPECT_FALSE(ui::isSpaceMouse(0x046d, 0xc52b));   // a Logitech Unifying receiver
    EXPECT_FALSE(ui::isSpaceMouse(0x256f, 0xc651));   // 3Dconnexion's CadMouse: an ordinary mouse
    EXPECT_FALSE(ui::isSpaceMouse(0x1234, 0xc626));
}

TEST(SpaceMouseReports, TranslationRotationAndButtonsParseLittleEndianSigned) {
    SpaceMouseState s;
    EXPECT_TRUE(ui::applySpaceMouseReport(s, axesReport(1, {350, -2, -32768})));
    EXPECT_EQ(s.translation, (std::array<int, 3>{350, -2, -32768}));
    EXPECT_EQ(s.rotation, (std::array<int, 3>{0, 0, 0}));
    EXPECT_TRUE(ui::applySpaceMouseReport(s, axesReport(2, {-350, 1, 32767})));
    EXPECT_EQ(s.rotation, (std::array<int, 3>{-350, 1, 32767}));
    EXPECT_EQ(s.translation[0], 350) << "a rotation report moved the translation";
    // Newer devices: all six axes in report 1.
    std::vector<uint8_t> six = axesReport(1, {10, 20, 30});
    const std::vector<uint8_t> rot = axesReport(2, {-40, -50, -60});
    six.insert(six.end(), rot.begin() + 1, rot.end());
    EXPECT_TRUE(ui::applySpaceMouseReport(s, six));
    EXPECT_EQ(s.translation, (std::array<int, 3>{10, 20, 30}));
    EXPECT_EQ(s.rotation, (std::array<int, 3>{-40, -50, -60}));
    const uint8_t buttons[] = {3, 0x05, 0x80};
    EXPECT_TRUE(ui::applySpaceMouseReport(s, buttons));
    EXPECT_EQ(s.buttons, 0x8005u);
}

TEST(SpaceMouseReports, ShortAndUnknownReportsChangeNothing) {
    SpaceMouseState s;
    s.translation = {1, 2, 3};
    const SpaceMouseState before = s;
    const std::vector<std::vector<uint8_t>> bad = {{}, {1}, {1, 0, 0, 0, 0, 0}, {2, 9, 9}, {3}, {4, 1}, {0x17, 100}};
    for (const auto& r : bad) EXPECT_FALSE(ui::applySpaceMouseReport(s, r)) << r.size() << " bytes";
    EXPECT_EQ(s.translation, before.translation);
    EXPECT_EQ(s.rotation, before.rotation);
    EXPECT_EQ(s.buttons, before.buttons);
    // Random bytes of every length: parsed or refused, never read past the end (ASan would say).
    std::mt19937 rng(7);
    for (int i = 0; i < 20000; ++i) {
        std::vector<uint8_t> r(size_t(rng() % 40));
        for (auto& b : r) b = uint8_t(rng());
        if (!r.empty() && i % 2 == 0) r[0] = uint8_t(1 + rng() % 3);
        ui::applySpaceMouseReport(s, r);
    }
}

TEST(SpaceMouseMotion, FullTwistForHalfASecondTurnsSixtyDegreesThroughTheOrbitRule) {
    renderer::Camera camera;
    camera.azimuthDeg = 0.0;
    SpaceMouseState s;
    s.rotation[2] = int(ui::kSpaceMouseFullScale);   // full twist clockwise
    for (int frame = 0; frame < 50; ++frame)   // 50 frames of 10 ms
        ui::applyOrbitInput(camera, ui::spaceMouseOrbit(s, 0.01, {}));
    EXPECT_NEAR(camera.azimuthDeg, -0.5 * ui::kSpaceMouseDegPerSec, 1e-3);
    EXPECT_EQ(camera.elevationDeg, renderer::Camera{}.elevationDeg);
    EXPECT_EQ(camera.distance, renderer::Camera{}.distance);
    // Inverted, at double speed: the other way, twice as far.
    renderer::Camera back;
    back.azimuthDeg = 0.0;
    for (int frame = 0; frame < 50; ++frame)
        ui::applyOrbitInput(back, ui::spaceMouseOrbit(s, 0.01, {.speed = 2.0, .invertRotation = true}));
    EXPECT_NEAR(back.azimuthDeg, 2.0 * 0.5 * ui::kSpaceMouseDegPerSec, 1e-3);
}

TEST(SpaceMouseMotion, PushZoomsTiltRaisesSlidePansAndRestNoiseDoesNothing) {
    const renderer::Camera start;
    SpaceMouseState s;
    s.translation = {8, -10, 12};   // inside the dead zone (5 % of 350 = 17.5)
    s.rotation = {-15, 17, 9};
    renderer::Camera c = start;
    EXPECT_FALSE(ui::applyOrbitInput(c, ui::spaceMouseOrbit(s, 0.05, {})));
    EXPECT_FALSE(s.deflected()) << "rest noise would keep the editor polling";
    s.rotation[1] = 300;   // roll: nothing follows it
    EXPECT_FALSE(s.deflected());
    s.rotation[0] = 18;
    EXPECT_TRUE(s.deflected());

    // Push away for one second: the distance halves (kSpaceMouseZoomPerSec), within the clamps.
    s = {};
    s.translation[1] = -int(ui::kSpaceMouseFullScale);
    c = start;
    for (int frame = 0; frame < 20; ++frame) ui::applyOrbitInput(c, ui::spaceMouseOrbit(s, 0.05, {}));
    EXPECT_NEAR(c.distance, start.distance * ui::kSpaceMouseZoomPerSec, 1e-6);

    // Tilt away: the elevation rises; half deflection beyond the dead zone is half the rate.
    s = {};
    s.rotation[0] = int(std::lround(ui::kSpaceMouseFullScale * (ui::kSpaceMouseDeadZone + 0.5 * (1 - ui::kSpaceMouseDeadZone))));
    c = start;
    ui::applyOrbitInput(c, ui::spaceMouseOrbit(s, 0.1, {}));
    EXPECT_NEAR(c.elevationDeg - start.elevationDeg, 0.5 * ui::kSpaceMouseDegPerSec * 0.1, 0.05);

    // Slide right and lift (z is down in HID): the image moves right and up.
    s = {};
    s.translation = {int(ui::kSpaceMouseFullScale), 0, -int(ui::kSpaceMouseFullScale)};
    c = start;
    ui::applyOrbitInput(c, ui::spaceMouseOrbit(s, 0.1, {}));
    EXPECT_NEAR(c.panPx.x, 0.1 * ui::kSpaceMousePanPxPerSec, 1e-3);
    EXPECT_NEAR(c.panPx.y, -0.1 * ui::kSpaceMousePanPxPerSec, 1e-3);

    // A stalled frame (2 s) moves no further than kSpaceMouseMaxStepSec; a clock going back, not at all.
    s = {};
    s.rotation[2] = int(ui::kSpaceMouseFullScale);
    c = start;
    ui::applyOrbitInput(c, ui::spaceMouseOrbit(s, 2.0, {}));
    EXPECT_NEAR(std::abs(c.azimuthDeg - start.azimuthDeg), ui::kSpaceMouseMaxStepSec * ui::kSpaceMouseDegPerSec, 1e-3);
    c = start;
    EXPECT_FALSE(ui::applyOrbitInput(c, ui::spaceMouseOrbit(s, -1.0, {})));
}

// == The polling loop against a fake HID backend

namespace {

struct FakeHid final : ui::HidBackend {
    std::vector<Device> devices;
    std::string refuse;                     // non-empty: open() fails with this
    std::deque<std::vector<uint8_t>> reports;
    bool unplugged = false, open_ = false;
    int enumerations = 0, opens = 0;

    std::vector<Device> enumerate() override {
        ++enumerations;
        return devices;
    }
    bool open(const std::string&, std::string& error) override {
        ++opens;
        if (!refuse.empty()) {
            error = refuse;
            return false;
        }
        return open_ = true;
    }
    int read(std::span<uint8_t> buffer) override {
        if (unplugged) return -1;
        if (reports.empty()) return 0;
        const std::vector<uint8_t> r = reports.front();
        reports.pop_front();
        std::copy(r.begin(), r.end(), buffer.begin());
        return int(r.size());
    }
    void close() override { open_ = false; }
};

} // namespace

TEST(SpaceMousePolling, FindsTheDeviceReadsItsReportsAndFollowsUnplugAndReplug) {
    auto owned = std::make_unique<FakeHid>();
    FakeHid& hid = *owned;
    hid.devices = {{"/dev/hidraw1", "USB Optical Mouse", 0x046d, 0xc077},
                   {"/dev/hidraw2", "SpaceNavigator", 0x046d, 0xc626}};
    ui::SpaceMouse mouse(std::move(owned));
    mouse.poll(0.0);
    ASSERT_TRUE(mouse.connected());
    EXPECT_EQ(mouse.status(), "SpaceNavigator (046d:c626)");
    EXPECT_EQ(hid.opens, 1) << "the ordinary mouse was opened";

    hid.reports = {axesReport(1, {100, 0, 0}), axesReport(2, {0, 0, -200}), axesReport(0x17, {1, 2, 3})};
    mouse.poll(0.1);
    EXPECT_EQ(mouse.state().translation[0], 100);
    EXPECT_EQ(mouse.state().rotation[2], -200);
    EXPECT_TRUE(hid.reports.empty());

    // Unplugged: the knob's last state is dropped (the camera must not keep spinning).
    hid.unplugged = true;
    mouse.poll(0.2);
    EXPECT_FALSE(mouse.connected());
    EXPECT_FALSE(hid.open_);
    EXPECT_EQ(mouse.state().rotation[2], 0);
    EXPECT_THAT(mouse.status(), HasSubstr("disconnected"));
    // Looked for again only after kRescanSeconds.
    hid.unplugged = false;
    const int scans = hid.enumerations;
    mouse.poll(0.2 + 0.5 * ui::SpaceMouse::kRescanSeconds);
    EXPECT_EQ(hid.enumerations, scans);
    mouse.poll(0.2 + ui::SpaceMouse::kRescanSeconds);
    EXPECT_TRUE(mouse.connected());
}

TEST(SpaceMousePolling, NoDeviceOrNoPermissionSaysSoAndAFloodOfReportsIsCapped) {
    auto owned = std::make_unique<FakeHid>();
    FakeHid& hid = *owned;
    ui::SpaceMouse mouse(std::move(owned));
    mouse.poll(0.0);
    EXPECT_FALSE(mouse.connected());
    EXPECT_EQ(mouse.status(), "no 3D mouse found");

    hid.devices = {{"/dev/hidraw5", "SpaceMouse Compact", 0x256f, 0xc635}};
    hid.refuse = "Permission denied";
    mouse.poll(ui::SpaceMouse::kRescanSeconds);
    EXPECT_FALSE(mouse.connected());
    EXPECT_THAT(mouse.status(), HasSubstr("SpaceMouse Compact (256f:c635)"));
    EXPECT_THAT(mouse.status(), HasSubstr("/dev/hidraw5"));
    EXPECT_THAT(mouse.status(), HasSubstr("Permission denied"));
    EXPECT_THAT(mouse.status(), HasSubstr("udev"));

    hid.refuse.clear();
    mouse.poll(2 * ui::SpaceMouse::kRescanSeconds);
    ASSERT_TRUE(mouse.connected());
    for (int i = 0; i < 3 * ui::SpaceMouse::kMaxReportsPerPoll; ++i) hid.reports.push_back(axesReport(1, {int16_t(i), 0, 0}));
    mouse.poll(2 * ui::SpaceMouse::kRescanSeconds + 0.01);
    EXPECT_EQ(hid.reports.size(), size_t(2 * ui::SpaceMouse::kMaxReportsPerPoll));
    EXPECT_EQ(mouse.state().translation[0], ui::SpaceMouse::kMaxReportsPerPoll - 1);
}
