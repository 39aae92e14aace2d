#!/usr/bin/env python3
"""Fleet throughput chart (SVG) from criterion's output, Python 3 stdlib only.

Reads every `target/criterion/fleet_<model>/<variant>/<size>/new/` written by
`cargo bench --bench fleet` (benchmark.json for the ids and the throughput,
estimates.json for the median time per iteration) and draws, per model, the
aircraft-steps per second against the fleet size on log-log axes, one line per
variant (ECS sequential/parallel, OOP sequential/parallel), with the line of
one million aircraft at 30 Hz (30 M aircraft-steps/s) for reference.

    python3 scripts/fleet_chart.py                      # writes docs/fleet_throughput.svg
    python3 scripts/fleet_chart.py --table              # also prints figure 13 and the fleet numbers (Markdown)
    python3 scripts/fleet_chart.py --all                # every benchmark's median (Markdown)
    python3 scripts/fleet_chart.py --criterion DIR --out FILE
    python3 scripts/fleet_chart.py --kernels            # docs/fleet_kernels.svg: the SIMD kernels
                                                        # (cargo bench -p fdm-fleet, fleet_kernels and
                                                        # geodetic_frame) against the scalar step
"""

import argparse
import json
import math
import os
import sys
import time
from xml.sax.saxutils import escape

VARIANTS = [
    # id, legend, colour, dashed
    ("ecs_par", "ECS, parallel", "#1f77b4", False),
    ("ecs_seq", "ECS, sequential", "#1f77b4", True),
    ("oop_par", "OOP Vec<Box<dyn>>, parallel", "#d62728", False),
    ("oop_seq", "OOP Vec<Box<dyn>>, sequential", "#d62728", True),
]
MODELS = [("palmer", "Palmer (Cessna 172, RK4, f64)"), ("bourg", "Bourg (6-DoF, Euler, f32)")]
TARGET_STEPS = 30e6  # one million aircraft at 30 Hz


def read_benchmarks(root):
    """Every benchmark under `root`: dicts with group, function, value, elements, median_ns."""
    found = []
    for dirpath, _dirs, files in os.walk(root):
        if os.path.basename(dirpath) != "new" or "benchmark.json" not in files:
            continue
        with open(os.path.join(dirpath, "benchmark.json")) as f:
            bench = json.load(f)
        with open(os.path.join(dirpath, "estimates.json")) as f:
            est = json.load(f)
        throughput = bench.get("throughput") or {}
        found.append(
            {
                "id": bench["full_id"],
                "group": bench["group_id"],
                "function": bench.get("function_id"),
                "value": bench.get("value_str"),
                "elements": throughput.get("Elements"),
                "median_ns": est["median"]["point_estimate"],
                "median_lo": est["median"]["confidence_interval"]["lower_bound"],
                "median_hi": est["median"]["confidence_interval"]["upper_bound"],
                "mtime": os.path.getmtime(os.path.join(dirpath, "estimates.json")),
            }
        )
    return sorted(found, key=lambda b: b["id"])


def fleet_series(benches):
    """{model: {variant: [(size, steps_per_s)]}} from the fleet_<model> groups."""
    series = {}
    for b in benches:
        if not b["group"].startswith("fleet_") or b["elements"] is None:
            continue
        model = b["group"][len("fleet_"):]
        rate = b["elements"] / (b["median_ns"] * 1e-9)
        series.setdefault(model, {}).setdefault(b["function"], []).append((int(b["value"]), rate))
    for variants in series.values():
        for points in variants.values():
            points.sort()
    return series


def si(x):
    for div, suffix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if x >= div:
            v = x / div
            return ("%.0f" % v if v >= 10 or v == int(v) else "%.1f" % v) + suffix
    return "%g" % x


def svg_chart(series, written):
    panel_w, panel_h = 470, 360
    left, right, top, bottom = 78, 16, 48, 58
    legend_h = 70
    width = len(MODELS) * panel_w
    height = panel_h + legend_h
    all_rates = [r for m in series.values() for pts in m.values() for _, r in pts] + [TARGET_STEPS]
    all_sizes = [n for m in series.values() for pts in m.values() for n, _ in pts] or [1, 10]
    y_lo = 10 ** math.floor(math.log10(min(all_rates)))
    y_hi = 10 ** math.ceil(math.log10(max(all_rates)))
    x_lo = 10 ** math.floor(math.log10(min(all_sizes)))
    x_hi = 10 ** math.ceil(math.log10(max(all_sizes)))
    if x_hi == x_lo:
        x_hi = x_lo * 10

    out = [
        '<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" viewBox="0 0 %d %d" '
        'font-family="DejaVu Sans, Helvetica, Arial, sans-serif" font-size="12">' % (width, height, width, height),
        '<rect width="100%" height="100%" fill="white"/>',
    ]
    for p, (model, title) in enumerate(MODELS):
        x0 = p * panel_w + left
        x1 = (p + 1) * panel_w - right
        y0 = top
        y1 = panel_h - bottom

        def px(n):
            return x0 + (math.log10(n) - math.log10(x_lo)) / (math.log10(x_hi) - math.log10(x_lo)) * (x1 - x0)

        def py(r):
            return y1 - (math.log10(r) - math.log10(y_lo)) / (math.log10(y_hi) - math.log10(y_lo)) * (y1 - y0)

        out.append('<text x="%.1f" y="24" text-anchor="middle" font-size="14" font-weight="bold">%s</text>'
                   % ((x0 + x1) / 2, escape(title)))
        # Grid and ticks.
        e = int(math.log10(y_lo))
        while 10 ** e <= y_hi:
            y = py(10 ** e)
            out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="#ddd"/>' % (x0, y, x1, y))
            out.append('<text x="%.1f" y="%.1f" text-anchor="end">%s</text>' % (x0 - 6, y + 4, si(10 ** e)))
            e += 1
        e = int(math.log10(x_lo))
        while 10 ** e <= x_hi:
            x = px(10 ** e)
            out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="#ddd"/>' % (x, y0, x, y1))
            out.append('<text x="%.1f" y="%.1f" text-anchor="middle">%s</text>' % (x, y1 + 16, si(10 ** e)))
            e += 1
        out.append('<rect x="%.1f" y="%.1f" width="%.1f" height="%.1f" fill="none" stroke="#444"/>'
                   % (x0, y0, x1 - x0, y1 - y0))
        out.append('<text x="%.1f" y="%.1f" text-anchor="middle">fleet size (aircraft)</text>'
                   % ((x0 + x1) / 2, y1 + 36))
        out.append('<text transform="translate(%.1f,%.1f) rotate(-90)" text-anchor="middle">'
                   'aircraft-steps per second</text>' % (x0 - 58, (y0 + y1) / 2))
        # One million aircraft at 30 Hz.
        ty = py(TARGET_STEPS)
        out.append('<line x1="%.1f" y1="%.1f" x2="%.1f" y2="%.1f" stroke="#2ca02c" stroke-dasharray="2,3"/>'
                   % (x0, ty, x1, ty))
        out.append('<text x="%.1f" y="%.1f" text-anchor="end" fill="#2ca02c">1 M aircraft at 30 Hz</text>'
                   % (x1 - 4, ty - 5))
        for variant, _legend, colour, dashed in VARIANTS:
            points = series.get(model, {}).get(variant, [])
            if not points:
                continue
            coords = " ".join("%.1f,%.1f" % (px(n), py(r)) for n, r in points)
            out.append('<polyline points="%s" fill="none" stroke="%s" stroke-width="2"%s/>'
                       % (coords, colour, ' stroke-dasharray="6,4"' if dashed else ""))
            for n, r in points:
                shape = ('<rect x="%.1f" y="%.1f" width="7" height="7" fill="%s"><title>%s</title></rect>'
                         % (px(n) - 3.5, py(r) - 3.5, colour, "%s %s %d: %s steps/s" % (model, variant, n, si(r)))
                         if variant.startswith("oop") else
                         '<circle cx="%.1f" cy="%.1f" r="3.5" fill="%s"><title>%s</title></circle>'
                         % (px(n), py(r), colour, "%s %s %d: %s steps/s" % (model, variant, n, si(r))))
                out.append(shape)
    # Legend.
    ly = panel_h + 10
    for i, (variant, legend, colour, dashed) in enumerate(VARIANTS):
        lx = 80 + (i % 2) * 420
        yy = ly + (i // 2) * 22
        out.append('<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="%s" stroke-width="2"%s/>'
                   % (lx, yy, lx + 36, yy, colour, ' stroke-dasharray="6,4"' if dashed else ""))
        out.append('<text x="%d" y="%d">%s</text>' % (lx + 44, yy + 4, escape(legend)))
    out.append('<text x="80" y="%d" fill="#555">Medians of criterion (benches/fleet.rs, one frame at 30 FPS per '
               'iteration), written %s; machine and load: BENCHMARKS.md.</text>' % (ly + 52, escape(written)))
    out.append("</svg>")
    return "\n".join(out) + "\n"


def fmt_ns(ns):
    if ns >= 1e9:
        return "%.3f s" % (ns / 1e9)
    if ns >= 1e6:
        return "%.2f ms" % (ns / 1e6)
    if ns >= 1e3:
        return "%.2f µs" % (ns / 1e3)
    return "%.1f ns" % ns


def fleet_table(series):
    lines = []
    for model, _title in MODELS:
        variants = series.get(model)
        if not variants:
            continue
        sizes = sorted({n for pts in variants.values() for n, _ in pts})
        rate = {(v, n): r for v, pts in variants.items() for n, r in pts}
        lines.append("%s, aircraft-steps/s (median):" % model)
        lines.append("")
        lines.append("| aircraft | ECS seq | ECS par | OOP seq | OOP par "
                     "| ECS/OOP seq | ECS/OOP par | ECS par/seq | OOP par/seq |")
        lines.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for n in sizes:
            def g(v):
                return rate.get((v, n))

            def ratio(a, b):
                return "%.2f" % (a / b) if a and b else "-"

            lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                "{:,}".format(n).replace(",", " "),
                *[("%.2f M" % (g(v) / 1e6)) if g(v) else "-" for v in ("ecs_seq", "ecs_par", "oop_seq", "oop_par")],
                ratio(g("ecs_seq"), g("oop_seq")),
                ratio(g("ecs_par"), g("oop_par")),
                ratio(g("ecs_par"), g("ecs_seq")),
                ratio(g("oop_par"), g("oop_seq")),
            ))
        lines.append("")
    return "\n".join(lines)


def fig13_table(benches):
    """Palmer against Bourg per frame rate (benches/palmer_vs_bourg.rs), or '' if not run."""
    med = {(b["function"], b["value"]): b["median_ns"] for b in benches if b["group"] == "fig13_100_frames"}
    fps = sorted({int(v) for _f, v in med}, key=int)
    if not fps:
        return ""
    lines = ["thesis figure 13, 100 frames (median):", "",
             "| FPS | Palmer | Bourg | Palmer / Bourg (time) | Bourg / Palmer |", "|---:|---:|---:|---:|---:|"]
    for f in fps:
        p, b = med.get(("palmer", str(f))), med.get(("bourg", str(f)))
        if p and b:
            lines.append("| %d | %s | %s | %.2f | %.2f |" % (f, fmt_ns(p), fmt_ns(b), p / b, b / p))
    return "\n".join(lines) + "\n"


def all_table(benches):
    lines = ["| benchmark | median | 95 % CI of the median | throughput |", "|---|---:|---:|---:|"]
    for b in benches:
        thr = ""
        if b["elements"]:
            thr = "%s elem/s" % si(b["elements"] / (b["median_ns"] * 1e-9))
        lines.append("| %s | %s | %s – %s | %s |" % (
            b["id"], fmt_ns(b["median_ns"]), fmt_ns(b["median_lo"]), fmt_ns(b["median_hi"]), thr))
    return "\n".join(lines) + "\n"


KERNEL_ROWS = [
    # (criterion id, label, target in aircraft-steps or -frames per second, or None)
    ("palmer_fleet/scalar/2t/1000000", "Palmer scalar step, 1M aircraft", None),
    ("palmer_fleet/exact/2t/1000000", "Palmer lanes exact, 1M", 18e6),
    ("palmer_fleet/fast/2t/1000000", "Palmer lanes fast, 1M", 30e6),
    ("bourg_fleet/scalar/2t/1000000", "Bourg scalar step, 1M", None),
    ("bourg_fleet/exact/2t/1000000", "Bourg lanes exact, 1M", 25e6),
    ("geodetic_frame/palmer/per_aircraft/2t/100000", "Palmer frame + geodesy, per aircraft, 100k", None),
    ("geodetic_frame/palmer/lanes_exact/2t/100000", "Palmer frame + geodesy, lanes exact, 100k", 10e6),
    ("geodetic_frame/palmer/lanes_fast/2t/100000", "Palmer frame + geodesy, lanes fast, 100k", 10e6),
    ("geodetic_frame/bourg/per_aircraft/2t/100000", "Bourg frame + geodesy, per aircraft, 100k", None),
    ("geodetic_frame/bourg/lanes/2t/100000", "Bourg frame + geodesy, lanes, 100k", 10e6),
]


def kernels_chart(benches):
    """Horizontal bars: 2-thread throughput of the fleet kernels and of whole frames, each
    target as a tick on its bar. Returns (svg text, rows found)."""
    by_id = {b["id"]: b for b in benches}
    rows = []
    for bid, label, target in KERNEL_ROWS:
        b = by_id.get(bid)
        if b and b["elements"]:
            rows.append((label, b["elements"] / b["median_ns"] * 1e9, target, b["mtime"]))
    if not rows:
        return None, rows
    left, width, bar, gap = 330, 420, 18, 8
    height = 60 + len(rows) * (bar + gap) + 40
    top = max(max(r[1] for r in rows), max(r[2] or 0 for r in rows)) * 1.1
    x = lambda v: left + width * v / top
    when = time.strftime("%Y-%m-%d %H:%M", time.gmtime(min(r[3] for r in rows)))
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">'
           % (left + width + 90, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="10" y="20" font-size="14">Fleet kernels on 2 threads (million aircraft-steps or '
           'aircraft-frames per second; | = target)</text>',
           '<text x="10" y="38" fill="#555">criterion medians, %s UTC (cargo bench -p fdm-fleet '
           '--bench fleet_kernels / geodetic_frame)</text>' % escape(when)]
    for i, (label, rate, target, _) in enumerate(rows):
        y = 55 + i * (bar + gap)
        colour = "#999999" if target is None else "#1f77b4"
        out.append('<text x="%d" y="%d" text-anchor="end">%s</text>' % (left - 6, y + 13, escape(label)))
        out.append('<rect x="%d" y="%d" width="%.1f" height="%d" fill="%s"/>' % (left, y, x(rate) - left, bar, colour))
        out.append('<text x="%.1f" y="%d">%.1f M</text>' % (x(rate) + 4, y + 13, rate / 1e6))
        if target:
            out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#d62728" stroke-width="2"/>'
                       % (x(target), y - 3, x(target), y + bar + 3))
    out.append('<line x1="%d" y1="50" x2="%d" y2="%d" stroke="black"/>' % (left, left, height - 35))
    out.append("</svg>\n")
    return "\n".join(out), rows


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.dirname(here)
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--criterion", default=os.path.join(repo, "target", "criterion"),
                    help="criterion's output directory (default: target/criterion)")
    ap.add_argument("--out", default=os.path.join(repo, "docs", "fleet_throughput.svg"),
                    help="SVG to write (default: docs/fleet_throughput.svg)")
    ap.add_argument("--table", action="store_true",
                    help="print figure 13 (Palmer/Bourg per FPS) and the fleet numbers as Markdown tables")
    ap.add_argument("--all", action="store_true", help="print every benchmark's median as a Markdown table")
    ap.add_argument("--kernels", action="store_true",
                    help="draw docs/fleet_kernels.svg from the fdm-fleet benchmarks instead")
    args = ap.parse_args()

    benches = read_benchmarks(args.criterion)
    if args.kernels:
        svg, rows = kernels_chart(benches)
        if svg is None:
            print("no fdm-fleet benchmarks under %s: run `cargo bench -p fdm-fleet` first" % args.criterion,
                  file=sys.stderr)
            return 1
        out = os.path.join(repo, "docs", "fleet_kernels.svg")
        with open(out, "w") as f:
            f.write(svg)
        for label, rate, target, _ in rows:
            print("| %s | %.2f M/s | %s |" % (label, rate / 1e6, "%.0f M" % (target / 1e6) if target else ""))
        print("wrote %s" % os.path.relpath(out), file=sys.stderr)
        return 0
    if args.all:
        sys.stdout.write(all_table(benches))
    series = fleet_series(benches)
    if not series:
        print("no fleet_* benchmarks under %s: run `cargo bench --bench fleet` first" % args.criterion,
              file=sys.stderr)
        return 1
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    stamps = [b["mtime"] for b in benches if b["group"].startswith("fleet_")]
    fmt = "%Y-%m-%d %H:%M"
    written = "%s to %s UTC" % (time.strftime(fmt, time.gmtime(min(stamps))), time.strftime("%H:%M", time.gmtime(max(stamps))))
    with open(args.out, "w") as f:
        f.write(svg_chart(series, written))
    if args.table:
        print(fig13_table(benches))
        print(fleet_table(series))
    print("wrote %s" % os.path.relpath(args.out), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
