// The regime tour's path in time (eased legs in log distance) and its step a frame.
#include "ui/regime_tour.h"

#include "ui/editor_state.h"
#include "ui/panels.h"

#include <algorithm>
#include <cmath>

namespace ui {

RegimeTour::RegimeTour(double startDistance, double nearDistance, double farDistance)
    : m_keys{startDistance, nearDistance, farDistance, startDistance} {
    std::array<double, 3> legs{};
    double total = 0.0;
    for (size_t i = 0; i < 3; ++i)
        total += legs[i] = std::abs(std::log(m_keys[i + 1] / m_keys[i]));
    for (size_t i = 0; i < 3; ++i)
        m_keyTimes[i + 1] = m_keyTimes[i] + (total > 0.0 ? kDurationS * legs[i] / total : kDurationS / 3.0);
    m_keyTimes[3] = kDurationS; // no rounding left over
}

double RegimeTour::distanceAt(double elapsedS) const {
    const double t = std::clamp(elapsedS, 0.0, kDurationS);
    size_t leg = 0;
    while (leg < 2 && t > m_keyTimes[leg + 1])
        ++leg;
    const double span = m_keyTimes[leg + 1] - m_keyTimes[leg];
    const double u = span > 0.0 ? (t - m_keyTimes[leg]) / span : 1.0;
    const double eased = u * u * (3.0 - 2.0 * u); // smoothstep: no jolt where a leg starts or ends
    return m_keys[leg] * std::pow(m_keys[leg + 1] / m_keys[leg], eased);
}

double RegimeTour::advance(double dtS) {
    m_elapsedS = std::min(m_elapsedS + std::max(dtS, 0.0), kDurationS);
    return distanceAt(m_elapsedS);
}

RegimeTour makeRegimeTour(double startDistance, double reconstructionNearer, double lowPassFarther) {
    const auto inRange = [](double d) { return std::clamp(d, kMinDistance, kMaxTourDistance); };
    const double nearD = inRange(0.8 * reconstructionNearer);
    const double farD = inRange(std::max(1.25 * lowPassFarther, 2.0 * nearD));
    return RegimeTour(inRange(startDistance), nearD, farD);
}

bool stepRegimeTour(EditorState& state, double dtS, bool userMovedCamera) {
    if (!state.tour) return false;
    if (userMovedCamera) { // the user takes the camera back: it stays where they put it
        state.tour.reset();
        return false;
    }
    state.camera.distance = state.tour->advance(dtS);
    if (state.tour->done()) state.tour.reset();
    return true;
}

} // namespace ui
