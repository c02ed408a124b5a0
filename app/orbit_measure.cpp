// The orbit's frames and their neighbour differences (orbit_measure.h).
#include "orbit_measure.h"

#include "renderer/errors.h"
#include "renderer/math/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace {

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

} // namespace

void checkOrbitStep(double stepDeg) {
    const double turns = 360.0 / stepDeg;
    if (!(stepDeg > 0.0 && stepDeg <= 180.0) || std::abs(turns - std::round(turns)) > 1e-6 || turns > 1e5)
        throw renderer::RenderError("--orbit " + fmt("%g", stepDeg) +
                                    ": expected a step in degrees that divides 360 (0.5, 1, 45, ...), at most 180");
}

OrbitSummary measureOrbit(const OrbitFrame& render, const renderer::SplatScene& scene, renderer::Camera camera,
                          int width, int height, double stepDeg) {
    checkOrbitStep(stepDeg);
    const int frames = int(std::lround(360.0 / stepDeg));
    OrbitSummary orbit;
    renderer::Image first, previous;
    const double startDeg = camera.azimuthDeg;
    for (int k = 0; k < frames; ++k) {
        camera.azimuthDeg = startDeg + stepDeg * k;
        const renderer::ImagePlane plane = makeImagePlane(camera, scene.centre, scene.radius, width, height, scene.axes);
        renderer::Image frame = render(plane);
        OrbitStep step{.azimuthDeg = camera.azimuthDeg, .axis = renderer::chooseTraversal(plane).axis};
        if (k > 0) step.rmse = renderer::compareImages(frame, previous).rmse;
        orbit.steps.push_back(step);
        if (k == 0) first = frame;
        if (k > 0 && step.rmse >= orbit.steps[orbit.worst].rmse) {
            orbit.worst = size_t(k);
            orbit.worstFrame = frame;
        }
        previous = std::move(frame);
    }
    // The turn closes: frame 0 against the last.
    orbit.steps[0].rmse = renderer::compareImages(first, previous).rmse;
    if (orbit.steps[0].rmse > orbit.steps[orbit.worst].rmse) {
        orbit.worst = 0;
        orbit.worstFrame = first;
    }
    std::vector<double> all, atSwitches;
    const size_t n = orbit.steps.size();
    const size_t side = std::min<size_t>(kLocalSteps, (n - 1) / 2);
    orbit.localSide = side;
    for (size_t k = 0; k < n; ++k) {
        OrbitStep& step = orbit.steps[k];
        all.push_back(step.rmse);
        std::vector<double> around;
        for (size_t d = 1; d <= side; ++d) {
            around.push_back(orbit.steps[(k + d) % n].rmse);
            around.push_back(orbit.steps[(k + n - d) % n].rmse);
        }
        const double local = renderer::nearestRankQuantile(around, 0.5);
        step.localRatio = local > 0.0 ? step.rmse / local : 0.0;
        if (step.localRatio > orbit.maxLocalRatio) {
            orbit.maxLocalRatio = step.localRatio;
            orbit.worstLocal = k;
        }
        if (step.axis != orbit.steps[(k + n - 1) % n].axis) {
            ++orbit.axisSwitches;
            atSwitches.push_back(step.rmse);
        } else {
            orbit.maxLocalRatioElsewhere = std::max(orbit.maxLocalRatioElsewhere, step.localRatio);
        }
    }
    orbit.medianRmse = renderer::nearestRankQuantile(all, 0.5);
    orbit.p90Rmse = renderer::nearestRankQuantile(all, 0.9);
    orbit.maxRmse = orbit.steps[orbit.worst].rmse;
    orbit.medianAtSwitches = renderer::nearestRankQuantile(atSwitches, 0.5);
    return orbit;
}

std::string orbitCsv(const OrbitSummary& orbit) {
    std::ostringstream csv;
    csv << "azimuth_deg,axis,rmse,local_ratio\n";
    for (const OrbitStep& s : orbit.steps)
        csv << fmt("%.4f", s.azimuthDeg) << "," << s.axis << "," << fmt("%.9g", s.rmse) << "," << fmt("%.6f", s.localRatio)
            << "\n";
    return csv.str();
}

std::string orbitSummaryText(const OrbitSummary& orbit, double stepDeg) {
    const double ratio = orbit.medianRmse > 0.0 ? orbit.maxRmse / orbit.medianRmse : 0.0;
    return std::to_string(orbit.steps.size()) + " frames, " + fmt("%g", stepDeg) +
           " deg apart: RMSE between neighbours median " + fmt("%.6f", orbit.medianRmse) + ", p90 " +
           fmt("%.6f", orbit.p90Rmse) + ", largest " + fmt("%.6f", orbit.maxRmse) + " (" + fmt("%.2f", ratio) +
           " x the median) at azimuth " + fmt("%g", orbit.steps[orbit.worst].azimuthDeg) + "; " +
           std::to_string(orbit.axisSwitches) + " axis switches, their median RMSE " +
           fmt("%.6f", orbit.medianAtSwitches) + "; against the " + std::to_string(2 * orbit.localSide) +
           " steps around it the largest jump is " + fmt("%.3f", orbit.maxLocalRatio) + " x at azimuth " +
           fmt("%g", orbit.steps[orbit.worstLocal].azimuthDeg) + ", elsewhere than an axis switch at most " +
           fmt("%.3f", orbit.maxLocalRatioElsewhere) + " x";
}
