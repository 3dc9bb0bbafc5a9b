#!/usr/bin/env python3
"""Image error against face count, ours and meshoptimizer, from bench_vs_meshoptimizer outputs.

    python3 bench/plot_simplify_vs_meshoptimizer.py OUT.png LOG [LOG ...]

Each LOG is the standard output of build/bench/bench_vs_meshoptimizer (any --only / --rply). One
panel per mesh, two rows (linear and 8-bit sRGB RMSE of the per-fragment image error, log scale):
ours (the filter's defaults), meshoptimizer's best setting at each level (the lowest error over the
settings the benchmark tried, so the envelope is optimistic for meshoptimizer), and meshoptimizer
on positions only. Writes OUT.png and the same figure as SVG beside it. Needs matplotlib.
"""
import os
import re
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402

ROW = re.compile(r"^\s+(\d+)% (ours|meshopt .+?)\s+(\d+)\s+([\d.e+-]+)\s+([\d.e+-]+)\s+([\d.e+-]+)")
MESH = re.compile(r"^== (.+?): \d+ vertices")


def parse(path):
    """{mesh: {'ours' | 'meshopt best' | 'meshopt positions only': {level: (faces, lin, 8bit)}}}"""
    meshes = defaultdict(lambda: defaultdict(dict))
    mesh = None
    for line in open(path):
        m = MESH.match(line)
        if m:
            mesh = os.path.basename(m.group(1))  # --rply inputs are named by their path
            continue
        m = ROW.match(line)
        if not (m and mesh):
            continue
        # Keyed by the level: meshoptimizer's settings may stop a few faces apart at one level.
        level, faces, lin, bit8 = int(m.group(1)), int(m.group(3)), float(m.group(4)), float(m.group(5))
        method = m.group(2).strip()
        levels = meshes[mesh]
        if method == "ours":
            levels["ours"][level] = (faces, lin, bit8)
        else:
            if method == "meshopt positions only":
                levels["meshopt positions only"][level] = (faces, lin, bit8)
            best = levels["meshopt best"].get(level, (faces, float("inf"), float("inf")))
            levels["meshopt best"][level] = (best[0], min(best[1], lin), min(best[2], bit8))
    return meshes


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out = sys.argv[1]
    meshes = {}
    for path in sys.argv[2:]:
        meshes.update(parse(path))
    if not meshes:
        sys.exit("no benchmark rows found in " + ", ".join(sys.argv[2:]))
    names = list(meshes)
    fig, axes = plt.subplots(2, len(names), figsize=(4.2 * len(names), 7), squeeze=False)
    styles = {"ours": dict(color="tab:red", marker="o", lw=2),
              "meshopt best": dict(color="tab:blue", marker="s"),
              "meshopt positions only": dict(color="tab:gray", marker="^", ls="--")}
    for col, name in enumerate(names):
        for row, label in enumerate(("linear RMSE", "8-bit sRGB RMSE")):
            ax = axes[row][col]
            for method, style in styles.items():
                points = sorted(meshes[name].get(method, {}).values())
                if points:
                    ax.plot([p[0] for p in points], [p[1 + row] for p in points], label=method, **style)
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.xaxis.set_minor_formatter(NullFormatter())
            ax.set_xlabel("faces")
            ax.set_ylabel(label)
            ax.grid(True, which="both", alpha=0.3)
            if row == 0:
                ax.set_title(name, fontsize=10)
    axes[0][0].legend(fontsize=8)
    fig.suptitle("Image error of the simplified radiance meshes (per-fragment, lower is better)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    fig.savefig(re.sub(r"\.png$", "", out) + ".svg")
    print("wrote", out)


if __name__ == "__main__":
    main()
