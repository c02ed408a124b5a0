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
#include "renderer/math/metrics.h"
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
                      const char* what) {
        GroundTruthStats stats;
        const auto t0 = std::chrono::steady_clock::now();
        Image gt = cachedGroundTruth(scene, plane, s, referenceOptions(), cache, {}, &stats);
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
        const SplatScene scene = buildSplatScene(hc.volume, hc.tf);
        const ImagePlane plane = makeImagePlane(hc.camera, scene.centre, scene.radius, hc.width, hc.height);
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
        const SplatScene scene = buildSplatScene(hc.volume, hc.tf);
        const ImagePlane plane = makeImagePlane(hc.camera, scene.centre, scene.radius, hc.width, hc.height);
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
// written per splat drawn; the slabs exist on the CPU only, so no frame time is given).
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
        const SplatScene scene = buildSplatScene(hc.volume, hc.tf);
        const ImagePlane plane = makeImagePlane(hc.camera, scene.centre, scene.radius, hc.width, hc.height);
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
          "the whole range measured (see the last table for the sizes of the differences).\n\n";
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
