#!/usr/bin/env python3
"""Markdown tables from renderer_bench JSON files (--benchmark_out), one per image size.

    bench_table.py [--errors ERRORS.json] bench_1920x1080.json [bench_512x512.json ...]

Each cell is the median frame time of the row's repetitions and their coefficient of variation (the bench
reports aggregates only); for the tiled front-to-back rows with and without occlusion culling a second table gives splats/s and each pass's
GPU time (medians), where a GPU spends its frame. Rows measured with errors add the PSNR against the
ground truth; --errors takes them from another run of the same rows, for the files of its size (a GPU bundle
cannot read the ground-truth cache, and the images agree with llvmpipe's to 2e-6).
"""
import json
import sys
from collections import defaultdict

SUFFIX = "/iterations:"


def setting_of(name):
    dataset, _, rest = name.partition("/")
    return dataset, rest.split(SUFFIX)[0]


def load(path):
    with open(path) as f:
        doc = json.load(f)
    runs = defaultdict(dict)   # (dataset, setting) -> {"median": row, "cv": row}
    for b in doc["benchmarks"]:
        if b.get("run_type") == "aggregate" and not b.get("error_occurred"):
            runs[setting_of(b["run_name"])][b["aggregate_name"]] = b
    return doc["context"], {k: v for k, v in runs.items() if "median" in v}


def ms(b):
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
    return b["real_time"] * scale


def fmt(x):
    return f"{x:.3g}" if x < 100 else f"{x:.0f}"


def frame_table(runs, datasets, settings, errors):
    lines = ["| setting | " + " | ".join(datasets) + " |", "|---" * (len(datasets) + 1) + "|"]
    for s in settings:
        cells = []
        for d in datasets:
            r = runs.get((d, s))
            cv = f" ±{r['cv']['real_time'] * 100:.0f}%" if r and "cv" in r else ""
            e = (errors.get((d, s)) or r or {}).get("median", {})
            db = f", {e['psnr_db']:.1f} dB" if r and "psnr_db" in e else ""
            cells.append(f"{fmt(ms(r['median']))} ms{cv}{db}" if r else "")
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    return lines


def pass_table(runs, datasets):
    lines = []
    for s in ("ewa/sheet-front-to-back/tiles-occlusion-culling", "ewa/sheet-front-to-back/tiles-no-occlusion-culling"):
        rows = [(d, runs[(d, s)]) for d in datasets if (d, s) in runs]
        if not rows:
            continue
        passes = sorted({k for _, r in rows for k in r["median"] if k.startswith("ms_")})
        lines += ["", f"`{s}`: splats, splats/s and GPU ms per pass (medians)", "",
                  "| scan | splats | M splats/s | " + " | ".join(p[3:] for p in passes) + " |",
                  "|---" * (len(passes) + 3) + "|"]
        for d, r in rows:
            med = lambda k: r["median"].get(k, 0.0)
            lines.append(f"| {d} | {med('splats'):,.0f} | {med('splats_per_s') / 1e6:.3g} | " +
                         " | ".join(f"{med(p):.2f}" for p in passes) + " |")
    return lines


def main(args):
    errors = {}
    if args[:1] == ["--errors"]:
        errors_context, errors = load(args[1])
        args = args[2:]
    for path in args:
        context, runs = load(path)
        same_size = errors and errors_context.get("resolution") == context.get("resolution")
        datasets = list(dict.fromkeys(d for d, _ in runs))
        settings = list(dict.fromkeys(s for _, s in runs))
        print(f"### {context.get('resolution', path)}: {context.get('GL_RENDERER', '')}".rstrip(": "))
        print()
        print("\n".join(frame_table(runs, datasets, settings, errors if same_size else {}) + pass_table(runs, datasets)))
        print()


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
