// `splatlab render --orbit STEP`: how much the image jumps between neighbouring views of a turn about
// the up axis. Object-aligned sheets slice along the volume axis nearest the view direction, and where
// a turn makes another axis the nearest the image "pops"; a renderer without popping changes as little
// there as anywhere else. Each frame is compared with the one before (RMSE of premultiplied RGBA, as
// error.md defines it), the last with the first.
#pragma once
#include "renderer/io/image.h"
#include "renderer/math/camera.h"
#include "renderer/model/splat_scene.h"

#include <functional>
#include <string>
#include <vector>

struct OrbitStep {
    double azimuthDeg = 0.0;   // this frame's camera azimuth
    int axis = 2;              // the volume axis its slices follow (chooseTraversal)
    double rmse = 0.0;         // against the frame before it (frame 0: against the last)
    double localRatio = 0.0;   // rmse over the median of the steps around it (kLocalSteps each side):
                               // a pop stands out of its neighbours, a view that changes fast does not
};

// The steps on each side a step is compared with (fewer when the turn has under 2 kLocalSteps + 1).
constexpr int kLocalSteps = 6;

struct OrbitSummary {
    std::vector<OrbitStep> steps;   // one a frame, in orbit order
    double medianRmse = 0.0, p90Rmse = 0.0, maxRmse = 0.0;
    size_t worst = 0;                  // the step with the largest RMSE
    int axisSwitches = 0;              // steps whose frame slices along another axis than the frame before
    double medianAtSwitches = 0.0;     // the median RMSE of those steps (0 without any)
    size_t localSide = 0;              // the steps on each side localRatio compared with
    size_t worstLocal = 0;             // the step with the largest localRatio
    double maxLocalRatio = 0.0, maxLocalRatioElsewhere = 0.0;   // over all steps; over those not switching axis
    renderer::Image worstFrame;        // the frame after the largest jump
};

// Throws RenderError naming --orbit for a step that does not divide 360 or is over 180 degrees.
void checkOrbitStep(double stepDeg);
// Draws one frame of the turn: GL, the CPU oracle or its image-aligned slabs.
using OrbitFrame = std::function<renderer::Image(const renderer::ImagePlane&)>;
// Renders 360 / stepDeg frames, the camera's azimuth advancing by stepDeg from `camera`'s, everything else
// as given (the step checked as checkOrbitStep does).
OrbitSummary measureOrbit(const OrbitFrame& render, const renderer::SplatScene& scene, renderer::Camera camera,
                          int width, int height, double stepDeg);

// One line a frame: "azimuth_deg,axis,rmse,local_ratio", under that header.
std::string orbitCsv(const OrbitSummary& orbit);
// "720 frames, 0.5 deg apart: RMSE between neighbours median ..., p90 ..., largest ... (... x the median)
// at azimuth ...; N axis switches, their median RMSE ...; against the steps around it the largest jump is
// ... x at azimuth ..., elsewhere than an axis switch at most ... x".
std::string orbitSummaryText(const OrbitSummary& orbit, double stepDeg);
