// `splatlab render`: a volume, or a session the editor saved, drawn headless to an image (GL, the CPU
// oracle, or image-aligned slabs on either), its frames timed; or an orbit that measures popping.
#pragma once
#include "scene_flags.h"

#include "renderer/oracle/image_slabs.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

// What only `render` sets: its outputs and how it runs.
struct RenderArgs {
    SceneArgs scene;
    int frames = 5, detailLevels = 0;
    bool cpu = false, counters = false;
    // --image-slabs (0: the volume's own sheets; NaN, not given: a session's slabs, else the sheets),
    // --post-classify, --supersample.
    renderer::SlabOptions slabs{.thickness = std::nan("")};
    std::string heatmap;
    double orbitStep = std::nan("");   // --orbit: the turn's step in degrees (NaN: no orbit)
    std::string orbitCsv;
    SplatFlags splat;
};

CLI::App* addRenderCommand(CLI::App& app, RenderArgs& args);
int runRender(RenderArgs args);
