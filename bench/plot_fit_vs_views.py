#!/usr/bin/env python3
"""Held-out error against the number of photographs, from bench_fit_capture outputs.

    python3 bench/plot_fit_vs_views.py OUT.png SERIES:VIEWS:LOG [SERIES:VIEWS:LOG ...]

writes OUT.png and OUT.svg (the same name with the other extension).

Each LOG is the standard output of
    build/bench/bench_fit_capture CAPTURE --models per-vertex,shared,auto --meshlab-colors COLORS.ply
(COLORS.ply from bench/meshlab_projection_capture.sh CAPTURE). SERIES groups the points of one
object/material (one panel each); VIEWS is the capture's raster count. Plotted per panel: the mean
over held-out views of the per-view RMS (8-bit sRGB) of the automatic fit, the per-vertex fit, the
shared fit, the constant mean colour (the per-vertex fit's), MeshLab's colour projection, and the
photographs' own noise. Needs matplotlib (the package's extra `plots`; scripts/setup.sh installs it
into build/python-venv): without it, a message says how to get it.
"""
import os
import re
import sys
from collections import defaultdict

try:
    import matplotlib

    matplotlib.use("Agg")
    matplotlib.rcParams["svg.fonttype"] = "none"  # SVG text stays text
    import matplotlib.pyplot as plt
except ImportError:
    plt = None


def parse(path):
    text = open(path).read()
    out = {}
    m = re.search(r"noise of the photographs .*?: ([\d.]+)", text)
    if m:
        out["noise"] = float(m.group(1))
    for model in ("per-vertex", "shared", "auto"):
        m = re.search(r"^" + re.escape(model) + r"\s+fit .*?\n\s+held-out mean RMS: fitted ([\d.]+)", text, re.M)
        if m:
            out[model] = float(m.group(1))
    m = re.search(r"reference constant \(per-vertex fit's mean colour\) ([\d.]+)", text)
    if m:
        out["constant"] = float(m.group(1))
    m = re.search(r"MeshLab projection colours: held-out mean RMS ([\d.]+)", text)
    if m:
        out["MeshLab projection"] = float(m.group(1))
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    if plt is None:
        sys.exit("plot_fit_vs_views.py: matplotlib is missing: install it with 'pip install matplotlib' (or the "
                 "package's extra: pip install '.[plots]'), e.g. build/python-venv/bin/python bench/plot_fit_vs_views.py")
    series = defaultdict(list)
    for arg in sys.argv[2:]:
        name, views, path = arg.split(":", 2)
        series[name].append((int(views), parse(path)))
    keys = [("auto", "automatic (default)", "-o"), ("per-vertex", "per-vertex", "--s"), ("shared", "shared", "--^"),
            ("constant", "constant mean colour", ":D"), ("MeshLab projection", "MeshLab projection", ":x"),
            ("noise", "photographs' noise", ":.")]
    fig, axes = plt.subplots(1, len(series), figsize=(5.2 * len(series), 4.0), squeeze=False)
    for ax, (name, points) in zip(axes[0], sorted(series.items())):
        points.sort()
        for key, label, style in keys:
            xs = [v for v, p in points if key in p]
            ys = [p[key] for v, p in points if key in p]
            if xs:
                ax.plot(xs, ys, style, label=label)
        ax.set_title(name)
        ax.set_xlabel("photographs in the capture (1/5 held out)")
        ax.set_ylabel("held-out RMS error (8-bit sRGB levels)")
        ax.set_xticks([v for v, _ in points])
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    stem = os.path.splitext(sys.argv[1])[0]
    for extension in (".png", ".svg"):
        fig.savefig(stem + extension, dpi=80)
    print(f"plot: {stem}.png, {stem}.svg")


if __name__ == "__main__":
    main()
