// `splatlab render` (render_command.h).
#include "render_command.h"

#include "cli_parse.h"
#include "orbit_measure.h"
#include "slab_frames.h"

#include "renderer/errors.h"
#include "renderer/gl/driver_profile.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/splat_renderer.h"
#include "renderer/io/atomic_file.h"
#include "renderer/io/image.h"
#include "renderer/oracle/near_layer.h"
#include "renderer/oracle/reference_renderer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <epoxy/gl.h>

using namespace renderer;

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void printCounters(const SplatCounters& c) {
    using ull = unsigned long long;
    // Every splat past the transparent and near-plane culls has its footprint (or, culled as hidden, the
    // bound the occlusion test projects) computed: what a hidden voxel still costs.
    const uint64_t computed = c.drawn + c.culledOffscreen + c.culledHuge + c.culledDegenerate + c.culledOccluded;
    std::printf("  footprints computed %llu, %.2f per splat drawn\n", ull(computed),
                c.drawn ? double(computed) / double(c.drawn) : 0.0);
    std::printf("  drawn %llu (reconstruction %llu, low-pass %llu, ewa %llu); culled transparent %llu, near %llu "
                "(near layer %llu, dropped %llu), offscreen %llu, huge %llu, degenerate %llu, hidden behind "
                "opaque %llu\n", ull(c.drawn), ull(c.drawnPerMode[0]), ull(c.drawnPerMode[1]), ull(c.drawnPerMode[2]),
                ull(c.culledTransparent), ull(c.culledNear), ull(c.nearLayer), ull(c.droppedNear),
                ull(c.culledOffscreen), ull(c.culledHuge), ull(c.culledDegenerate), ull(c.culledOccluded));
}

// What a guard left out of the image, on stderr: kernels at the near plane beyond what the near layer takes
// (near_layer.h), all of them where a frame has no near layer, and, where SplatSettings::maxFootprintFraction
// is set, huge footprints. Counted when the counters ran; otherwise found on the CPU (findNearKernels) or,
// without a near layer, the near plane is checked against the volume's nearest voxel.
void reportDroppedSplats(const Scene& s, const SplatCounters* counted) {
    const bool layer = hasNearLayer(s.plane, s.settings);
    const uint64_t dropped = counted ? counted->droppedNear
                                     : layer ? findNearKernels(s.scene, s.plane, s.settings).dropped : 0;
    if (dropped > 0)
        std::fprintf(stderr, "note: %llu kernels at the near plane (%g from the eye) were left out: the near "
                             "layer takes at most %d\n", (unsigned long long)dropped, s.plane.nearDepth, kMaxNearKernels);
    if (counted) {
        if (!layer && counted->culledNear > 0)
            std::fprintf(stderr, "note: %llu splats whose kernels reach the near plane (%g from the eye) were not "
                                 "drawn; the ground truth clips their kernels there\n",
                         (unsigned long long)counted->culledNear, s.plane.nearDepth);
        if (counted->culledHuge > 0)
            std::fprintf(stderr, "note: %llu footprints wider than %g image diagonals were not drawn\n",
                         (unsigned long long)counted->culledHuge, s.settings.maxFootprintFraction);
        return;
    }
    const glm::dvec2 depths = s.plane.depthRange(s.scene.dims, s.scene.origin, s.scene.spacing);
    if (!layer && !s.plane.orthographic && depths.x <= s.plane.nearDepth)
        std::fprintf(stderr, "note: the near plane (%g from the eye) cuts the volume: voxels nearer are not drawn "
                             "(the ground truth clips their kernels there); --counters counts them\n",
                     s.plane.nearDepth);
}

// Milliseconds with three significant digits or more: 98.1, 5.02, 0.213.
std::string formatMs(double ms) {
    char text[32];
    std::snprintf(text, sizeof text, ms >= 100.0 ? "%.0f" : ms >= 10.0 ? "%.1f" : ms >= 1.0 ? "%.2f" : "%.3f", ms);
    return text;
}

// How the frames composite: the setting, or the image-aligned slabs that replace it.
std::string compositingText(const Scene& s, const RenderArgs& ra) {
    return ra.slabs.thickness > 0.0 ? slabsText(ra.slabs) : compositingName(s.settings.compositing);
}

// render --orbit: the turn drawn with GL or on the CPU (the oracle, or its image-aligned slabs), its
// summary printed, the frame after the largest jump to --out.
int runOrbit(const Scene& s, const SceneArgs& a, const RenderArgs& ra) {
    OrbitSummary orbit;
    std::string device = "CPU oracle (double)";
    if (ra.slabs.thickness > 0.0) {
        const SlabFrames slabs(ra.cpu);
        orbit = measureOrbit([&](const ImagePlane& p) { return slabs.render(s.scene, p, s.settings, ra.slabs); },
                             s.scene, s.camera, s.plane.width, s.plane.height, ra.orbitStep);
        device = slabs.device();
    } else if (ra.cpu) {
        orbit = measureOrbit([&](const ImagePlane& p) { return renderReference(s.scene, p, s.settings); }, s.scene,
                             s.camera, s.plane.width, s.plane.height, ra.orbitStep);
    } else {
        auto context = HeadlessGl::create();
        SplatRenderer gl;
        gl.setScene(s.scene);
        orbit = measureOrbit([&](const ImagePlane& p) { gl.render(p, s.settings); return gl.readback(); }, s.scene,
                             s.camera, s.plane.width, s.plane.height, ra.orbitStep);
        device = glRendererName();
    }
    if (!ra.orbitCsv.empty()) writeFileAtomically(ra.orbitCsv, orbitCsv(orbit));
    writeImage(orbit.worstFrame, a.out, s.background.data());
    std::printf("%s: %s, %s, %s on %s\n", a.out.c_str(), orbitSummaryText(orbit, ra.orbitStep).c_str(),
                filterModeName(s.settings.filter), compositingText(s, ra).c_str(), device.c_str());
    return 0;
}

// What a session's slabs refuse (a view they do not take) says whose slabs they were and how to draw the
// session's sheets instead.
template <class Draw>
auto sayingSessionSlabs(bool sessionSlabs, Draw draw) {
    try {
        return draw();
    } catch (const RenderError& e) {
        if (!sessionSlabs) throw;
        throw RenderError(std::string(e.what()) + " (the session's image-aligned slabs: --image-slabs 0 draws its sheets)");
    }
}

} // namespace

int runRender(RenderArgs ra) {
    const SceneArgs& a = ra.scene;
    const int frames = ra.frames;
    // --image-slabs THICKNESS draws slabs, 0 the volume's sheets; without it a session's slabs, as the
    // editor ends its still view in them, else the sheets.
    const bool slabFlag = !std::isnan(ra.slabs.thickness);
    if (!slabFlag) ra.slabs.thickness = 0.0;
    if ((ra.slabs.postClassified || ra.slabs.supersample != 0) && ra.slabs.thickness == 0.0)
        throw CLI::ValidationError(ra.slabs.postClassified ? "--post-classify" : "--supersample",
                                   "applies to image-aligned slabs: give --image-slabs THICKNESS");
    if (ra.slabs.thickness != 0.0) {
        if (!(ra.slabs.thickness >= kMinSlabThickness && ra.slabs.thickness <= kMaxSlabThickness))
            throw CLI::ValidationError("--image-slabs", "expected a slab thickness of 0.05 to 64 voxels");
        if (!ra.heatmap.empty()) throw CLI::ValidationError("--heatmap", "the image-aligned slabs draw no heatmap");
    }
    const bool cpu = ra.cpu;
    if (frames < 1) throw CLI::ValidationError("--frames", "must be >= 1");
    checkImageWritable(a.out);   // before the volume loads and the frames render
    const bool orbit = !std::isnan(ra.orbitStep) || !ra.orbitCsv.empty();
    if (orbit) {
        checkOrbitStep(ra.orbitStep);
        if (!ra.heatmap.empty() || ra.counters)
            throw CLI::ValidationError("--orbit", "compares whole frames: not with --heatmap or --counters");
        if (!ra.orbitCsv.empty()) checkFileReplaceable(ra.orbitCsv);
    }
    if (ra.detailLevels < 0 || ra.detailLevels > 3) throw CLI::ValidationError("--detail-levels", "must be 0 to 3 halvings");
    Scene s = buildScene(a, ra.splat, ra.detailLevels);
    const bool sessionSlabs = !slabFlag && s.slabs;
    if (sessionSlabs) {
        if (!ra.heatmap.empty())
            throw CLI::ValidationError("--heatmap", "the session's image-aligned slabs draw no heatmap (--image-slabs 0 "
                                                    "draws its sheets)");
        ra.slabs = *s.slabs;
    }
    if (orbit) return sayingSessionSlabs(sessionSlabs, [&] { return runOrbit(s, a, ra); });
    s.settings.heatmap = !ra.heatmap.empty();
    if (s.settings.heatmap && std::filesystem::path(ra.heatmap).lexically_normal() ==
                                  std::filesystem::path(a.out).lexically_normal())
        throw CLI::ValidationError("--heatmap", "'" + ra.heatmap + "' is also --out: the heatmap would replace the image");
    if (s.settings.heatmap) checkImageWritable(ra.heatmap);
    s.settings.counters = ra.counters;
    Image heatmap;
    Image image;
    std::vector<double> ms;
    std::string device;
    SplatCounters counters;
    SlabCounters slabs;
    if (ra.slabs.thickness > 0.0) {   // timed as the GL frames are: the first one (programs, set-up) untimed
        const SlabFrames renderer(cpu);
        device = renderer.device();
        for (int i = cpu ? 0 : -1; i < frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            image = sayingSessionSlabs(sessionSlabs,
                                       [&] { return renderer.render(s.scene, s.plane, s.settings, ra.slabs, &slabs); });
            if (i >= 0) ms.push_back(msSince(t0));
        }
        counters = slabs.splats;
    } else if (cpu) {
        device = "CPU oracle (double)";
        for (int i = 0; i < frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            image = renderReference(s.scene, s.plane, s.settings, &counters, s.settings.heatmap ? &heatmap : nullptr);
            ms.push_back(msSince(t0));
        }
    } else {
        auto context = HeadlessGl::create();
        device = glRendererName();
        if (a.session.empty() && cullingByDriver(ra.splat))
            s.settings.occlusionCulling = driverProfile(device).occlusionCulling;
        SplatRenderer gl;
        gl.setScene(s.scene);
        gl.render(s.plane, s.settings);   // warm-up: shader compilation and first-use costs
        glFinish();
        for (int i = 0; i < frames; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            gl.render(s.plane, s.settings);
            glFinish();
            ms.push_back(msSince(t0));
        }
        gl.collectTimers();   // the last frame's, finished by its glFinish
        std::string passes;
        for (int i = 0; i < kGpuPasses; ++i)
            if (const double passMs = gl.stats().passMs[size_t(i)]; passMs > 0.0)
                passes += (passes.empty() ? "" : ", ") + std::string(gpuPassName(GpuPass(i))) + " " + formatMs(passMs);
        std::printf("  GPU %s ms in the last frame: %s\n", formatMs(gl.stats().gpuMs).c_str(),
                    passes.empty() ? "no pass ran" : passes.c_str());
        const int readBacks = gl.stats().readBacks;
        image = gl.readback();
        std::printf("  %d buffer read-back%s inside the last frame%s\n", readBacks, readBacks == 1 ? "" : "s",
                    gl.stats().redone ? "; its lists, sized from the frames before, were too short: drawn again" : "");
        if (s.settings.heatmap) heatmap = gl.readbackHeatmap();
        if (ra.counters) {   // one more frame with the GPU's counters on (they wait for the frame)
            SplatSettings counted = s.settings;
            counted.counters = true;
            gl.render(s.plane, counted);
            counters = gl.stats().counters;
            if (gl.stats().tiles)
                std::printf("  %llu splat-tile pairs composited\n", (unsigned long long)gl.stats().tileEntries);
            else
                std::printf("  %llu fragments passed (all passes)\n", (unsigned long long)gl.stats().fragments);
        }
        std::printf("  %s, %.2f GPU bytes per voxel (the scene), %.1f MiB more for the frame's passes\n",
                    primitiveName(gl.stats()).c_str(), double(gl.sceneBytes()) / double(s.scene.classes.size()),
                    double(gl.workingBytes()) / (1024.0 * 1024.0));
        if (const std::string splits = tileSplitsText(gl.stats()); !splits.empty()) std::printf("  %s\n", splits.c_str());
    }
    writeImage(image, a.out, s.background.data());
    if (s.settings.heatmap) writeImage(heatmap, ra.heatmap, s.background.data());
    std::sort(ms.begin(), ms.end());
    std::printf("%s: %dx%d, %zu splats, %s, %s, %.2f ms/frame (median of %d) on %s\n", a.out.c_str(),
                s.plane.width, s.plane.height, s.scene.visibleCount(), filterModeName(s.settings.filter),
                compositingText(s, ra).c_str(), ms[ms.size() / 2], frames, device.c_str());
    if (ra.counters) printCounters(counters);
    if (ra.slabs.thickness > 0.0 && ra.counters)
        std::printf("  %llu slabs; %llu footprint pixels written %llu times into them (%.2f slabs each)\n",
                    (unsigned long long)slabs.slabs, (unsigned long long)slabs.footprintPixels,
                    (unsigned long long)slabs.slabWrites,
                    slabs.footprintPixels ? double(slabs.slabWrites) / double(slabs.footprintPixels) : 0.0);
    reportDroppedSplats(s, ra.counters || ra.cpu ? &counters : nullptr);
    return 0;
}
CLI::App* addRenderCommand(CLI::App& app, RenderArgs& ra) {
    CLI::App* render = app.add_subcommand("render", "Render a volume headless to an image (PNG, EXR, ...)");
    addSceneOptions(render, ra.scene);
    addSplatFlags(render, ra.splat);
    render->add_option("--heatmap", ra.heatmap, "Also write the filter-mode heatmap (red reconstruction, green "
                                                "low-pass, blue EWA, weighted by opacity)");
    render->add_flag("--counters", ra.counters, "Print splats per filter and per cull (GL: counted on the GPU)");
    render->add_option("--frames", ra.frames, "Timed frames (the median is printed)")->capture_default_str();
    render->add_option("--detail-levels", ra.detailLevels, "Far views: draw the volume halved up to this many times "
                       "where the level's kernels stay under the low-pass threshold and keep the optical mass "
                       "(0: full resolution)")->capture_default_str();
    render->add_flag("--cpu", ra.cpu, "Render with the double-precision CPU oracle instead of GL");
    render->add_option("--image-slabs", ra.slabs.thickness, "Composite slabs parallel to the image, this many voxels thick, "
                       "instead of the volume's slices (front to back; kernels prepared on the CPU, pixels on the GPU or "
                       "with --cpu on the CPU oracle; 0: the slices, also for a --session whose slabs are on)");
    render->add_flag("--post-classify", ra.slabs.postClassified, "With --image-slabs: apply the TF to each slab's "
                     "reconstructed value instead of to each voxel (1D TFs)");
    render->add_option("--supersample", ra.slabs.supersample, "With --image-slabs: S x S samples a pixel, resolved by "
                       "the ground truth's 1-px Gaussian (0..4; 0: one sample, no resolve)");
    render->add_option("--orbit", ra.orbitStep, "Turn the camera about the up axis in steps of this many degrees and "
                                                "print how much each frame differs from the one before (popping); "
                                                "--out gets the frame after the largest jump");
    render->add_option("--orbit-csv", ra.orbitCsv, "With --orbit: each frame's azimuth, slice axis and RMSE");
    render->add_option("--session", ra.scene.session,
                       "Render a session saved by the editor: its volume, TF, window, camera, settings, background and, "
                       "where they are on, image-aligned slabs (a volume argument replaces its volume; --size, --out, "
                       "--heatmap, --counters, --frames, --cpu and --image-slabs still apply)");
    render->get_option("volume")->required(false);
    return render;
}
