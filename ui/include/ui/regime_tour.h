// The regime tour: the camera dollies from near to far and back, so that a class watches the regions of
// the view change filter (the heatmap shows it). Plain data, no ImGui: the Filters panel starts a tour,
// the app advances it a frame at a time, and any camera input of the user's ends it.
#pragma once
#include "renderer/math/camera.h"

#include <array>

namespace ui {

class RegimeTour {
  public:
    static constexpr double kDurationS = 8.0; // the whole tour: a few seconds, slow enough to watch

    // From `startDistance` to `nearDistance`, out to `farDistance`, and back to `startDistance` (camera
    // distances in bounding radii). Each leg eases in and out, its length in time in proportion to its
    // change of log distance, since a kernel's size on screen goes as 1 / depth.
    RegimeTour(double startDistance, double nearDistance, double farDistance);

    // The camera distance `elapsedS` seconds into the tour (after kDurationS: back at the start).
    double distanceAt(double elapsedS) const;
    // Moves the tour on by dtS seconds; returns the camera distance now.
    double advance(double dtS);
    bool done() const { return m_elapsedS >= kDurationS; }
    double nearDistance() const { return m_keys[1]; }
    double farDistance() const { return m_keys[2]; }

  private:
    std::array<double, 4> m_keys{};     // distances: start, near, far, start
    std::array<double, 4> m_keyTimes{}; // seconds at which the tour passes each
    double m_elapsedS = 0.0;
};

// The farthest a tour goes, in bounding radii: past the wheel's kMaxDistance (20), since small volumes in
// small viewports reach the low-pass regime only farther out (headsq at 955 x 497 px: 35 radii).
constexpr double kMaxTourDistance = 100.0;

// A tour for the view with these filter depths (renderer::filterDepths, in bounding radii): near puts the
// volume's centre at 0.8 x the reconstruction depth (its front in reconstruction), far at 1.25 x the
// low-pass depth (its back in low-pass), within kMinDistance..kMaxTourDistance; far is at least twice
// near, so a view whose regimes lie close together still moves.
RegimeTour makeRegimeTour(double startDistance, double reconstructionNearer, double lowPassFarther);

struct EditorState;
// One frame of a tour under way: ends it when the user moved the camera this frame (a drag, the wheel, a
// double-click, a camera setting, the 3D mouse), else moves state.camera's distance on by dtS. Returns
// whether the tour moved the camera (the app then renders).
bool stepRegimeTour(EditorState& state, double dtS, bool userMovedCamera);

} // namespace ui
