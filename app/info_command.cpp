// `splatlab info`: what a volume file holds (info_command.h).
#include "info_command.h"

#include "console_progress.h"

#include "renderer/errors.h"
#include "renderer/model/gradients.h"
#include "renderer/model/volume.h"
#include "renderer/model/window.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

using namespace renderer;

int runInfo(const std::string& path, const std::optional<RawOptions>& raw, bool gradients) {
    const Volume v = loadVolume(path, raw);
    std::printf("%s\n", path.c_str());
    std::printf("  dims     %d x %d x %d (%zu voxels)\n", v.dims.x, v.dims.y, v.dims.z, v.voxelCount());
    std::printf("  type     %s\n", voxelTypeName(v.type));
    std::printf("  spacing  %g x %g x %g\n", v.spacing.x, v.spacing.y, v.spacing.z);
    std::printf("  origin   %g, %g, %g\n", v.origin.x, v.origin.y, v.origin.z);
    if (v.directions != glm::dmat3(1.0)) {
        const glm::dmat3& d = v.directions;
        Volume axesOnly;   // no voxels: what alignment leaves of these axes, for the message
        axesOnly.name = path;   // an error names the file
        axesOnly.directions = d;
        const Volume aligned = alignedToWorldAxes(axesOnly);
        const glm::dmat3 left = aligned.directions;
        std::string how = left == glm::dmat3(1.0)   ? "in the file's world frame: the voxels are reordered"
                          : glm::determinant(d) > 0 ? "in the file's world frame: the view turns with them"
                                                    : "in the file's world frame: x reversed, the view turns with them";
        if (aligned.resampled) try {
                const Volume grid = worldGrid(v);
                char text[160];
                std::snprintf(text, sizeof text, "%d x %d x %d at %g x %g x %g", grid.dims.x, grid.dims.y,
                              grid.dims.z, grid.spacing.x, grid.spacing.y, grid.spacing.z);
                how = std::string("sheared: render and the editor resample the voxels (trilinear) onto a grid along "
                                  "the world axes, ") + text;
            } catch (const LoadError& e) {
                how = "sheared, and too far to resample: " + e.reason();
            }
        // Axes a header rounded: alignment takes them as the orthonormal axes nearest them.
        const bool rounded = !aligned.resampled && !isRotation(d) && !isRotation(glm::dmat3(-d[0], d[1], d[2]));
        std::printf("  axes     x (%g, %g, %g)  y (%g, %g, %g)  z (%g, %g, %g)  (%s%s)\n",
                    d[0].x, d[0].y, d[0].z, d[1].x, d[1].y, d[1].z, d[2].x, d[2].y, d[2].z, how.c_str(),
                    rounded ? "; rounded cosines, not quite orthonormal: drawn as the orthonormal axes nearest them"
                            : "");
    }
    std::printf("  range    %g .. %g\n", v.range.lo, v.range.hi);
    const ValueRange p = percentileWindow(v, 1.0, 99.0);
    std::printf("  p1..p99  %g .. %g\n", p.lo, p.hi);
    // Histogram summary: 16 bins, each with its share of voxels and a bar.
    const Histogram h = computeHistogram(v, 16);
    std::printf("  histogram (16 bins)\n");
    const double width = (double(h.range.hi) - h.range.lo) / double(h.counts.size());
    for (size_t i = 0; i < h.counts.size(); ++i) {
        const double share = double(h.counts[i]) / double(std::max<size_t>(v.voxelCount(), 1));
        const int bar = int(std::lround(std::sqrt(share) * 40));   // sqrt: small bins stay visible
        std::printf("  %10.4g .. %-10.4g %6.2f%% %s\n", h.range.lo + width * double(i),
                    h.range.lo + width * double(i + 1), 100.0 * share, std::string(size_t(bar), '#').c_str());
    }
    if (gradients) {
        // Central differences in object units: data units per unit of spacing (per mm for CT).
        std::fprintf(stderr, "gradients\n");
        const auto t0 = std::chrono::steady_clock::now();
        const auto field = computeGradients(v, printProgress);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        const GradientStats g = gradientMagnitudeStats(*field);
        std::printf("  gradient magnitude  min %g  mean %g  p99 %g  max %g (data units per object unit; "
                    "%.0f ms)\n",
                    g.min, g.mean, g.p99, g.max, ms);
    }
    return 0;
}
