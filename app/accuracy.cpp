// `splatlab accuracy` (see accuracy.h): four measurements, each a table in the report:
// (1) hard case x filter mode against the ground truth, with thumbnails; (2) the paper's claims per image
// region on the grazing checkerboard (000 fig. 8); (3) the same minified cases at lower density, which
// separates per-footprint filtering from compositing; (4) Marschner-Lobb error against kernel scale.
// Ground truths come from the cache and are computed once.
#include "accuracy.h"

#include "renderer/oracle/accuracy.h"
#include "renderer/io/atomic_file.h"
#include "renderer/oracle/ground_truth.h"
#include "renderer/oracle/hard_cases.h"
#include "renderer/oracle/image_slabs.h"
#include "renderer/errors.h"
#include "renderer/io/volume_io.h"
#include "renderer/math/metrics.h"
#include "renderer/model/gradients.h"
#include "renderer/model/procedural.h"
#include "renderer/oracle/reference_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <thread>

namespace {

using namespace renderer;
namespace fs = std::filesystem;

constexpr FilterMode kModes[] = {FilterMode::Ewa, FilterMode::Reconstruction, FilterMode::LowPass,
                                 FilterMode::Adaptive};

// The hard-case suite's reference settings (tests/unit/test_hard_cases.cpp): within 4e-4 RMSE of
// supersample 5 on these scenes.
GroundTruthOptions referenceOptions() {
    GroundTruthOptions o;
    o.supersample = 2;
    o.tolerance = 1e-4;
    return o;
}

struct Report {
    fs::path out, images, cache;
    std::ostringstream md;
    int computed = 0, cached = 0; // references, for the timing line

    // Writes `image` as a thumbnail and returns its markdown, `width` px wide on the page.
    std::string thumbnail(const Image& image, const std::string& name, int width) {
        writeImage(image, images / (name + ".png"));
        return "<img src=\"images/accuracy/" + name + ".png\" width=\"" + std::to_string(width) + "\">";
    }
    Image groundTruth(const SplatScene& scene, const ImagePlane& plane, const SplatSettings& s,
                      const char* what, bool postClassified = false, bool unfiltered = false) {
        GroundTruthStats stats;
        const auto t0 = std::chrono::steady_clock::now();
        GroundTruthOptions options = referenceOptions();
        options.postClassified = postClassified;
        if (unfiltered) options.supersample = 0;   // one ray through each pixel centre, no V_h
        Image gt = cachedGroundTruth(scene, plane, s, options, cache, {}, &stats);
        ++(stats.fromCache ? cached : computed);
        std::fprintf(stderr, "  %-40s reference %s (%.1f s)\n", what,
                     stats.fromCache ? "from the cache" : "computed",
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        if (!stats.cacheNote.empty()) std::fprintf(stderr, "  note: not cached: %s\n", stats.cacheNote.c_str());
        return gt;
    }
};

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

Image render(const SplatScene& scene, const ImagePlane& plane, SplatSettings s, FilterMode mode) {
    s.filter = mode;
    return renderReference(scene, plane, s);
}

// A hard case's scene and its view.
std::pair<SplatScene, ImagePlane> sceneAndPlane(const HardCase& hc) {
    SplatScene scene = buildSplatScene(hc.volume, hc.tf);
    const ImagePlane plane = makeImagePlane(hc.camera, scene.centre, scene.radius, hc.width, hc.height);
    return {std::move(scene), plane};
}

// Whether --only leaves the hard case `name` in (all are in without it).
bool selected(const AccuracyArgs& args, const std::string& name) {
    return args.only.empty() || std::find(args.only.begin(), args.only.end(), name) != args.only.end();
}

// 1. Hard case x filter mode, after `heading` (the near-eye views: the same table).
void hardCaseTable(Report& r, const AccuracyArgs& args, const std::vector<HardCase>& cases,
                   const char* heading) {
    r.md << heading
         << "| case | what it stresses | ground truth | EWA | reconstruction | low-pass | adaptive |\n"
            "|---|---|---|---|---|---|---|\n";
    for (const HardCase& hc : cases) {
        if (!selected(args, hc.name))
            continue;
        const auto [scene, plane] = sceneAndPlane(hc);
        const Image gt = r.groundTruth(scene, plane, hc.settings, hc.name.c_str());
        r.md << "| " << hc.name << " | " << hc.what << " | " << r.thumbnail(gt, hc.name + "_gt", 96);
        for (FilterMode m : kModes) {
            const Image img = render(scene, plane, hc.settings, m);
            const ImageError e = compareImages(img, gt);
            r.md << " | " << r.thumbnail(img, hc.name + "_" + filterModeName(m), 96) << "<br>"
                 << fmt("%.1f", e.psnrDb) << " (" << fmt("%.4f", e.rmse) << ")";
        }
        r.md << " |\n";
    }
    r.md << "\n";
}

// 2. 000 fig. 8 per region.
void claimsTable(Report& r, const AccuracyArgs& args) {
    const ViewedVolume v =
        grazingCheckerboard(args.board, std::max(1, args.board / 64), args.board / 4, args.board / 8);
    const SplatScene scene = buildSplatScene(v.volume, v.tf);
    const ImagePlane plane = makeImagePlane(v.camera, scene.centre, scene.radius, v.width, v.height);
    const SplatSettings settings;
    const Image gt = r.groundTruth(scene, plane, settings, v.name.c_str());
    const std::vector<Region> regions = classifyPixels(scene, plane, settings);
    // Region map: magnified red, transition grey, minified blue.
    Image map(plane.width, plane.height);
    for (size_t i = 0; i < regions.size(); ++i) {
        const float colours[4][3] = {{0, 0, 0}, {0.9f, 0.2f, 0.2f}, {0.5f, 0.5f, 0.5f}, {0.2f, 0.3f, 0.9f}};
        for (int c = 0; c < 3; ++c)
            map.rgba[4 * i + size_t(c)] = colours[int(regions[i])][c];
        map.rgba[4 * i + 3] = 1.0f;
    }
    size_t counts[4] = {};
    for (Region g : regions)
        ++counts[int(g)];
    const int thumb = 2 * plane.width;
    r.md << "## The paper's claims per region (000 fig. 8)\n\n"
         << "The " << args.board << "x" << args.board << "x3 checkerboard (cells of "
         << std::max(1, args.board / 64)
         << " voxels, every voxel opaque, black and white) seen from just above its near edge at "
         << plane.width << "x" << plane.height
         << " px, 40 degree fov (`grazingCheckerboard` in `renderer/oracle/accuracy.h`). Regions come from the "
            "classifier: "
            "a pixel is magnified (red) when its centre ray enters and leaves the volume at depths that both "
            "take "
            "reconstruction only at the paper's `c_min` = 0.3, minified (blue) when both take low-pass only "
            "at "
            "`c_max` = 2 (1 + tan^2(fovY/2) (1 + (W/H)^2)), transition (grey) otherwise. A taller image cannot show both "
            "ends: "
            "minified depths (0.7 f_px c_max voxels) grow with the image height, and the board must span a "
            "depth "
            "ratio of c_max / c_min ~ 8.4.\n\n"
         << "| ground truth | region map | EWA | reconstruction | low-pass | adaptive "
            "|\n|---|---|---|---|---|---|\n| "
         << r.thumbnail(gt, "board_gt", thumb) << " | " << r.thumbnail(map, "board_regions", thumb);
    std::vector<std::pair<FilterMode, Image>> images;
    for (FilterMode m : kModes) {
        images.emplace_back(m, render(scene, plane, settings, m));
        r.md << " | " << r.thumbnail(images.back().second, std::string("board_") + filterModeName(m), thumb);
    }
    r.md << " |\n\nPSNR in dB (RMSE, mean alpha minus the ground truth's) per region:\n\n"
            "| region | pixels | EWA | reconstruction | low-pass | adaptive |\n|---|---|---|---|---|---|\n";
    for (Region g : {Region::Magnified, Region::Transition, Region::Minified}) {
        r.md << "| " << regionName(g) << " | " << counts[int(g)];
        for (const auto& [m, img] : images) {
            const RegionError e = regionError(img, gt, regions, g);
            if (e.pixels == 0) {
                r.md << " | -";
                continue;
            }
            r.md << " | " << fmt("%.2f", e.psnrDb) << " (" << fmt("%.4f", e.rmse) << ", "
                 << fmt("%+.3f", e.alphaBias) << ")";
        }
        r.md << " |\n";
    }
    const ImageError whole = compareImages(images[0].second, gt);
    r.md << "| whole image | " << regions.size() << " | " << fmt("%.2f", whole.psnrDb);
    for (size_t i = 1; i < images.size(); ++i)
        r.md << " | " << fmt("%.2f", compareImages(images[i].second, gt).psnrDb);
    r.md << " |\n\n";
}

// 3. Filter order: the minified hard cases at falling density.
void densityTable(Report& r, const AccuracyArgs& args, const std::vector<HardCase>& cases) {
    r.md << "## Filtering each footprint vs filtering the image\n\n"
            "EWA band-limits each footprint before compositing (001 eq. 8); the ground truth composites and "
            "then "
            "filters (001 eq. 6). The two agree where the attenuation is constant over a footprint and "
            "opacity is "
            "linear in optical depth (001 eq. 7); at opaque silhouettes and opaque sub-pixel detail they do "
            "not: "
            "1 - exp(-blurred depth) covers more than the blurred 1 - exp(-depth). Lowering the density "
            "makes the "
            "volume optically thin, where the assumptions hold. PSNR in dB:\n\n"
            "| case | density | ground truth mean / max alpha | EWA | reconstruction | low-pass "
            "|\n|---|---|---|---|---|---|\n";
    for (const HardCase& hc : cases) {
        if (hc.name != "far-away" && hc.name != "zebra" && hc.name != "grazing-checkerboard") continue;
        if (!selected(args, hc.name))
            continue;
        const auto [scene, plane] = sceneAndPlane(hc);
        for (double density : {1.0, 0.1, 0.01}) {
            SplatSettings s = hc.settings;
            s.density = density;
            const Image gt =
                r.groundTruth(scene, plane, s, (hc.name + " density " + fmt("%g", density)).c_str());
            const ImageStats st = imageStats(gt);
            r.md << "| " << hc.name << " | " << density << " | " << fmt("%.3f", st.meanAlpha) << " / "
                 << fmt("%.3f", st.maxAlpha);
            for (FilterMode m : {FilterMode::Ewa, FilterMode::Reconstruction, FilterMode::LowPass})
                r.md << " | " << fmt("%.2f", compareImages(render(scene, plane, s, m), gt).psnrDb);
            r.md << " |\n";
        }
    }
    r.md << "\n";
}

// 4. Kernel scale on Marschner-Lobb, against two references: the ground truth of the same kernels (the
// splatting error alone) and the ground truth of the signal sampled twice as finely (kernel scale 0.7,
// density halved so the extinction per object unit matches): what the kernels lose of the signal.
void kernelScaleTable(Report& r, const AccuracyArgs& args) {
    const int n = args.marschnerLobb, size = 4 * n; // 16^3 at 64x64: voxels ~3 px apart
    const TransferFunction tf = fromSharedPoints(
        "ramp", {{0.0, {0.2, 0.4, 1.0}, 0.0}, {0.3, {0.3, 0.9, 0.4}, 0.24}, {1.0, {1.0, 0.8, 0.3}, 0.8}});
    const ValueRange window{0.0f, 1.0f}; // the signal's range, so both grids classify alike
    const Camera camera{30, 20, 2.5, 30.0};
    const SplatScene coarse = buildSplatScene(makeMarschnerLobb(n), tf, window);
    Volume fineVolume = makeMarschnerLobb(2 * n - 1);
    fineVolume.spacing = glm::dvec3(0.5);
    const SplatScene fine = buildSplatScene(fineVolume, tf, window);
    const ImagePlane plane = makeImagePlane(camera, coarse.centre, coarse.radius, size, size);
    SplatSettings fineSettings;
    fineSettings.density = 0.5;
    const Image signal = r.groundTruth(fine, plane, fineSettings, "marschner-lobb, fine grid");
    r.md << "## Kernel scale on Marschner-Lobb\n\n"
         << n << "^3 samples of Marschner-Lobb at " << size << "x" << size
         << " px (camera 30,20,2.5,30). Each cell: PSNR in dB against the ground truth of the same kernels "
            "(the "
            "splatting error alone) / against the ground truth of the signal sampled at "
         << 2 * n - 1
         << "^3 with kernel scale 0.7 (what a viewer compares with: splatting plus what the kernels "
            "blur or ripple). Low-pass-only ignores the kernel scale (its footprint is V_h alone).\n\n"
            "| kernel scale | kernels vs signal | EWA | reconstruction | low-pass | adaptive "
            "|\n|---|---|---|---|---|---|\n";
    for (double k : args.kernelScales) {
        SplatSettings s;
        s.kernelScale = k;
        const Image gt =
            r.groundTruth(coarse, plane, s, ("marschner-lobb, kernel scale " + fmt("%g", k)).c_str());
        r.md << "| " << fmt("%.2f", k) << " | " << fmt("%.2f", compareImages(gt, signal).psnrDb);
        for (FilterMode m : kModes) {
            const Image img = render(coarse, plane, s, m);
            r.md << " | " << fmt("%.2f", compareImages(img, gt).psnrDb) << " / "
                 << fmt("%.2f", compareImages(img, signal).psnrDb);
        }
        r.md << " |\n";
    }
    r.md << "\n";
}

// 5. Image-aligned slabs (image_slabs.h) against object-aligned compositing: the thickness curve per
// hard case, for EWA and reconstruction-only, with the work each thickness costs (footprint pixels
// written per splat drawn; frame times are renderer_bench's image-slabs rows, docs/speed.md).
void slabTable(Report& r, const AccuracyArgs& args, const std::vector<HardCase>& cases) {
    constexpr double kThicknesses[] = {1.0, 0.5, 0.25};
    r.md << "## Image-aligned slabs\n\n"
            "Slabs parallel to the image (shells about the eye; `renderer/oracle/image_slabs.h`), each kernel's "
            "share of a slab integrated in closed form along the ray, composited front to back, against the "
            "volume's own slices (splat every sample; sheets front to back). Same views and truths as the hard "
            "cases. PSNR in dB; the last column is the work over one sheet: slabs written per footprint pixel "
            "(slabs 1 / 0.5 / 0.25 voxels thick; a sheet writes each once).\n\n"
            "| case | filter | splat every sample | sheets | slabs 1 | slabs 0.5 | slabs 0.25 | slabs per footprint pixel |\n"
            "|---|---|---|---|---|---|---|---|\n";
    for (const HardCase& hc : cases) {
        if (!selected(args, hc.name)) continue;
        const auto [scene, plane] = sceneAndPlane(hc);
        const Image gt = r.groundTruth(scene, plane, hc.settings, hc.name.c_str());
        for (FilterMode m : {FilterMode::Ewa, FilterMode::Reconstruction}) {
            SplatSettings s = hc.settings;
            s.filter = m;
            r.md << "| " << hc.name << " | " << filterModeName(m) << " | "
                 << fmt("%.2f", compareImages(renderReference(scene, plane, s), gt).psnrDb);
            s.compositing = Compositing::SheetFrontToBack;
            r.md << " | " << fmt("%.2f", compareImages(renderReference(scene, plane, s), gt).psnrDb);
            std::string work;
            for (double t : kThicknesses) {
                SlabCounters c;
                r.md << " | " << fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, s, SlabOptions{t}, &c), gt).psnrDb);
                work += (work.empty() ? "" : " / ") +
                        fmt("%.1f", double(c.slabWrites) / double(std::max<uint64_t>(1, c.footprintPixels)));
            }
            r.md << " | " << work << " |\n";
        }
    }
    r.md << "\n";
}

// 6. Post-classified slabs against their own truth (GroundTruthOptions::postClassified), and how far
// that truth lies from the pre-classified one (what the model itself changes).
void postClassifiedTable(Report& r, const AccuracyArgs& args, const std::vector<HardCase>& cases) {
    r.md << "## Post-classified slabs\n\n"
            "Each slab classifies its kernels' mean value (`renderer/model/post_classification.h`); the truth "
            "applies the TF to the kernels' mean value along each exact ray, then filters as the other truth "
            "does. PSNR in dB against that truth, for slabs 1 / 0.5 / 0.25 voxels thick; the first column is "
            "the post-classified truth against the pre-classified one. \"2x2\": reconstruction-only slabs 0.25 "
            "voxels thick, 2x2 samples a pixel resolved by the truth's pixel filter (`render --supersample 2`); "
            "\"shaded\": the same, lit per fragment, against the shaded post-classified truth. A view whose "
            "kernels reach the near plane has no post-classified slabs (the near layer is pre-classified): "
            "\"-\".\n\n"
            "| case | truths apart | EWA | reconstruction | low-pass | 2x2 | shaded, 2x2 |\n"
            "|---|---|---|---|---|---|---|\n";
    for (const HardCase& hc : cases) {
        if (!selected(args, hc.name)) continue;
        const auto [scene, plane] = sceneAndPlane(hc);
        const Image pre = r.groundTruth(scene, plane, hc.settings, hc.name.c_str());
        const Image post = r.groundTruth(scene, plane, hc.settings, (hc.name + ", post-classified").c_str(), true);
        r.md << "| " << hc.name << " | " << fmt("%.2f", compareImages(post, pre).psnrDb);
        for (FilterMode m : {FilterMode::Ewa, FilterMode::Reconstruction, FilterMode::LowPass}) {
            SplatSettings s = hc.settings;
            s.filter = m;
            std::string cell;
            try {
                for (double t : {1.0, 0.5, 0.25})
                    cell += (cell.empty() ? "" : " / ") +
                            fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, s, SlabOptions{t, true}), post).psnrDb);
            } catch (const RenderError&) {
                cell = "-";
            }
            r.md << " | " << cell;
        }
        SplatScene lit = scene;
        addGradients(lit, *computeGradients(hc.volume));
        SplatSettings s = hc.settings;
        s.filter = FilterMode::Reconstruction;
        const SlabOptions resolved{0.25, true, 2};
        std::string cells = "- | -";
        try {
            cells = fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, s, resolved), post).psnrDb);
            s.shading = SplatSettings::Shading::PerFragment;
            const Image shaded = r.groundTruth(lit, plane, s, (hc.name + ", post-classified, shaded").c_str(), true);
            cells += " | " + fmt("%.2f", compareImages(renderImageAlignedSlabs(lit, plane, s, resolved), shaded).psnrDb);
        } catch (const RenderError&) {
        }
        r.md << " | " << cells << " |\n";
    }
    r.md << "\n";
}

// 7. The bundled scans, at their default view and minified (8 bounding radii), 128x128: object-aligned
// sheets against image-aligned slabs, pre- and post-classified, EWA against reconstruction-only.
void scanTable(Report& r) {
    struct Scan {
        const char* name;
        const char* file;
        const char* tf;
        glm::dvec3 up;
    };
    const fs::path volumes = fs::path(SPLATLAB_ASSET_DIR) / "volumes";
    const Scan scans[] = {{"bonsai", "bonsai.nhdr", "presets/bonsai.json", {0, 0, 1}},
                          {"headsq", "headsq.nhdr", "ct-skin-bone", {0, 0, -1}}};
    r.md << "## Scans: the filter order on real data\n\n"
            "The bundled scans at 128x128 (`assets/volumes`), at the default view (2.5 bounding radii) and "
            "minified (8). PSNR in dB; pre-classified images against the pre-classified truth, post-classified "
            "against theirs; slabs 0.5 voxels thick, post-classified 0.5 / 0.25. The last column holds the "
            "post-classified reconstruction-only slabs against the unfiltered post-classified truth (one ray "
            "through each pixel centre, no V_h): the model without the question of how a pixel is filtered. "
            "\"2x2\" holds them 0.25 voxels thick with 2x2 samples a pixel resolved by the truth's own pixel "
            "filter (`render --supersample 2`), against the filtered truth.\n\n"
            "| scan | distance | EWA sheets | EWA slabs | reconstruction sheets | reconstruction slabs | "
            "post-classified EWA slabs | post-classified reconstruction slabs | the same, unfiltered truth | 2x2 |\n"
            "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Scan& scan : scans) {
        const Volume volume = loadVolume(volumes / scan.file);
        const std::string tfSpec = std::string(scan.tf).find('/') != std::string::npos
                                       ? (fs::path(SPLATLAB_ASSET_DIR) / scan.tf).string()
                                       : std::string(scan.tf);
        const SplatScene scene = buildSplatScene(volume, transferFunctionFromSpec(tfSpec));
        for (double distance : {2.5, 8.0}) {
            Camera camera{30, 20, distance, 30.0};
            camera.up = scan.up;
            const ImagePlane plane = makeImagePlane(camera, scene.centre, scene.radius, 128, 128, scene.axes);
            const std::string what = std::string(scan.name) + " at " + fmt("%g", distance);
            const Image pre = r.groundTruth(scene, plane, SplatSettings{}, what.c_str());
            const Image post = r.groundTruth(scene, plane, SplatSettings{}, (what + ", post-classified").c_str(), true);
            r.md << "| " << scan.name << " | " << fmt("%g", distance);
            for (FilterMode m : {FilterMode::Ewa, FilterMode::Reconstruction}) {
                SplatSettings s;
                s.filter = m;
                s.compositing = Compositing::SheetFrontToBack;
                r.md << " | " << fmt("%.2f", compareImages(renderReference(scene, plane, s), pre).psnrDb) << " | "
                     << fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, s, SlabOptions{0.5}), pre).psnrDb);
            }
            for (FilterMode m : {FilterMode::Ewa, FilterMode::Reconstruction}) {
                SplatSettings s;
                s.filter = m;
                r.md << " | " << fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, s, SlabOptions{0.5, true}), post).psnrDb)
                     << " / " << fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, s, SlabOptions{0.25, true}), post).psnrDb);
            }
            const Image bare =
                r.groundTruth(scene, plane, SplatSettings{}, (what + ", post-classified, unfiltered").c_str(), true, true);
            SplatSettings reconstruction;
            reconstruction.filter = FilterMode::Reconstruction;
            r.md << " | " << fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, reconstruction, SlabOptions{0.5, true}), bare).psnrDb)
                 << " / " << fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, reconstruction, SlabOptions{0.25, true}), bare).psnrDb)
                 << " | " << fmt("%.2f", compareImages(renderImageAlignedSlabs(scene, plane, reconstruction, SlabOptions{0.25, true, 2}), post).psnrDb)
                 << " |\n";
        }
    }
    r.md << "\n";
}

} // namespace

CLI::App* addAccuracyCommand(CLI::App& app, AccuracyArgs& a) {
    auto* cmd = app.add_subcommand("accuracy", "Measure every filter mode against the ground truth; write "
                                               "OUT/accuracy.md and its thumbnails");
    cmd->add_option("--out", a.out, "Folder for accuracy.md (images go to OUT/images/accuracy)")
        ->capture_default_str();
    cmd->add_option("--cache", a.cache, "Ground-truth cache folder (default: ~/.cache/splatlab/reference)");
    cmd->add_option("--only", a.only, "Hard cases to run, by name (default: all)")->delimiter(',');
    cmd->add_option("--board", a.board, "Grazing checkerboard side in voxels (image board/4 x board/8)")
        ->capture_default_str()
        ->check(CLI::Range(64, 2048));
    cmd->add_option("--marschner-lobb", a.marschnerLobb, "Marschner-Lobb samples per axis for the sweep")
        ->capture_default_str()
        ->check(CLI::Range(4, 64));
    cmd->add_option("--kernel-scales", a.kernelScales, "Kernel scales of the sweep")
        ->delimiter(',')
        ->capture_default_str();
    return cmd;
}

int runAccuracy(const AccuracyArgs& a) {
    for (double k : a.kernelScales)
        if (!(k > 0.05 && k <= 10))
            throw CLI::ValidationError("--kernel-scales", "each must be in (0.05, 10]");
    const std::vector<HardCase> cases = hardCases(1);   // built once: the tables below share them
    for (const std::string& name : a.only)
        if (std::none_of(cases.begin(), cases.end(), [&](const HardCase& hc) { return hc.name == name; })) {
            std::string known;
            for (const HardCase& hc : cases) known += (known.empty() ? "" : ", ") + hc.name;
            throw CLI::ValidationError("--only", "no hard case '" + name + "' (known: " + known + ")");
        }
    const auto t0 = std::chrono::steady_clock::now();
    Report r;
    r.out = a.out;
    r.images = r.out / "images" / "accuracy";
    r.cache = a.cache.empty() ? defaultGroundTruthCacheDir() : fs::path(a.cache);
    fs::create_directories(r.images);
    std::ostringstream body;
    std::swap(r.md, body);
    hardCaseTable(r, a, cases,
                  "## Hard cases\n\n"
                  "PSNR in dB (RMSE in brackets) of the CPU splat image against the ground truth, 48x48 px, "
                  "splat-every-sample compositing, kernel scale 0.7. Thumbnails: ground truth, then EWA, "
                  "reconstruction, low-pass, adaptive (PNG over black).\n\n");
    hardCaseTable(
        r, a, nearEyeCases(),
        "## Near the eye\n\n"
        "Kernels whose cutoff ellipsoid reaches the near plane are not splatted (EWA's affine "
        "projection fails there), nor those within two cutoff depths behind it (where it still errs: "
        "taking only the first, the optical depth came out 7.5 % and 9 % over in these views, 36.9 and "
        "32.0 dB). The near layer integrates them along each pixel's ray from the near plane on, as the "
        "ground truth does, as two sheets (those at the plane over those behind) in front of the splats "
        "(`renderer/oracle/near_layer.h`). Before it they were left out: in EWA voxel-centre scored "
        "11.9 dB with 55 % of its optical depth missing, thin-ball 19.4 dB with 33 % missing, "
        "near-plane 22.8 dB. Same settings as the hard cases. At 128x128 on the GL path (before, "
        "after, truth; 10.4 -> 33.5 dB and 19.4 -> 50.6 "
"dB):\n\n<img src=\"images/near-eye/voxel-centre.png\" width=\"400\"> "
        "<img src=\"images/near-eye/thin-ball.png\" width=\"400\">\n\n");
    claimsTable(r, a);
    densityTable(r, a, cases);
    kernelScaleTable(r, a);
    slabTable(r, a, cases);
    postClassifiedTable(r, a, cases);
    if (a.only.empty()) scanTable(r);   // the whole report only: its truths take minutes
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ostringstream md;
    md << "# Accuracy\n\n"
          "Generated by `splatlab accuracy --out docs` (ground truths are cached: a second run only splats). "
          "Error "
          "is the RMSE of premultiplied RGBA against the ground truth with its PSNR, as [error.md](error.md) "
          "defines it; "
          "references use supersample 2 and tolerance 1e-4 (the hard-case suite's settings). This run took "
       << fmt("%.0f", seconds) << " s on " << std::thread::hardware_concurrency() << " threads ("
       << r.computed << " references computed, " << r.cached << " from the cache).\n\n"
       << "What the tables show:\n\n"
          "- **The paper's claims hold per region** on the grazing checkerboard: where the classifier says "
          "minified, "
          "reconstruction-only errs more than EWA (moire of a checker finer than the pixels); where it says "
          "magnified, low-pass-only errs far more (1-px dots with holes between them); adaptive EWA at the "
          "paper's "
          "`c_min`/`c_max` stays within about 0.1 dB of EWA in every region. Reconstruction-only is as good "
          "as EWA "
          "or slightly better where magnified, as 000 sec. 3.2 argues.\n"
          "- **Reconstruction-only beating EWA on some hard cases is not a bug in either image.** It comes "
          "from "
          "filtering before compositing: with opaque material EWA's 1-px blur of optical depth saturates "
          "(1 - exp(-blurred depth) > blurred (1 - exp(-depth))), so opaque silhouettes and opaque sub-pixel "
          "stripes spread by about a pixel, which the reference (filter after compositing, 001 eq. 6) does "
          "not. "
          "At density 0.1 and 0.01, where the volume is optically thin and 001 eq. 7 holds, EWA beats "
          "reconstruction-only by 2 to 30 dB on the same scenes.\n"
          "- **Kernel scale**: against the same kernels' ground truth the splatting error falls slowly as "
          "the scale "
          "shrinks; against the finely sampled signal smaller scales also lose less of the signal's detail, "
          "over "
          "the whole range measured (see its table for the sizes of the differences).\n"
          "- **Image-aligned slabs** remove the object-aligned slices' error where kernels overlap in depth: "
          "EWA at 0.5 voxels gains 1.6 dB on Marschner-Lobb (44.2 -> 45.8; splat every sample 39.7), 5.2 on "
          "huge-coordinates, 6.4 on nan-inf-values, 1.7 on orthographic. Thinner than 0.5 gains at most "
          "0.19 dB here for twice the work (9.4 -> 17.8 slabs a footprint pixel), so 0.5 voxels is the "
          "pre-classified default. And they do not pop (cli.md, the orbit).\n"
          "- **Thin slabs do not change the filter order.** On the opaque minified cases and the scans "
          "minified, EWA stays where it was at every thickness (zebra 25.01, grazing checkerboard 21.26, "
          "bonsai at 8 radii 28.09) and reconstruction-only stays ahead (27.96, 25.50, 31.23). Thin slabs "
          "make each slab optically thin, but EWA's error there lies across the image, not along the ray: "
          "it spreads an opaque stripe's optical depth over the gap beside it, and many slabs of that cover "
          "the gap, where the truth (composite, then filter) sees through it. So the 1 dB that EWA was to "
          "win over reconstruction-only in minified opaque views cannot come from slabs.\n"
          "- **Post-classified slabs reproduce their model; resolved from 2x2 samples a pixel, also its "
          "filtered truth.** Where magnified they follow their own truth (Marschner-Lobb 45.7 dB, 34.6 dB "
          "from the pre-classified truth). On the scans, one sample a pixel scores 24.7-31.1 dB against "
          "the filtered truth but 44.5-62.8 against one ray through each pixel centre: a sharp TF applied "
          "after reconstruction makes edges finer than a pixel, which one sample aliases and the truth "
          "filters. Reconstruction-only slabs 0.25 voxels thick, with 2x2 samples a pixel resolved by the "
          "truth's own pixel filter, score 54.9-68.2 dB on the scans and 48.8-88.0 on the hard cases, "
          "shaded 49.3-90.0, at four times the work. EWA's low-pass does not help: it averages values "
          "before the TF sees them, so a thin leaf's value mixes with the air beside it. A TF band thinner "
          "than a slab aliases along the ray too: the step-edge test scores 12.5 / 23.5 / 29.9 dB at 1 / "
          "0.5 / 0.25 voxels. Pre-integrated classification would address that; it is not built.\n\n";
    if (!a.only.empty()) {
        md << "This run covers only the hard cases named by `--only`:";
        for (const std::string& name : a.only) md << " " << name;
        md << ".\n\n";
    }
    md << r.md.str();
    writeFileAtomically(r.out / "accuracy.md", md.str());
    std::printf("%s: written in %.1f s\n", (r.out / "accuracy.md").string().c_str(), seconds);
    return 0;
}
