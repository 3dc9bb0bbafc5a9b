#!/usr/bin/env python3
"""plot_error_vs_memory.py TABLE.txt OUT.svg [TITLE]: the image error against memory plot of the main
job, from the table compare_radiance_meshes prints. A row's series is its name up to the last '_'
(e.g. 'radiance_250' -> 'radiance'); the original (no error) is skipped.

Writes OUT.svg and OUT.png (the same name with the other extension) with matplotlib (the package's
extra `plots`; scripts/setup.sh installs it into build/python-venv). Without matplotlib it says so on
stderr and writes a plain SVG (no PNG) by hand, so the main job still has its plot."""
import os
import sys

COLOURS = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]
X_LABEL = "memory (MB)"
Y_LABEL = "mean image RMSE (linear)"


def read_rows(path):
    """(series, name, memory MB, RMSE) per simplified mesh of the table."""
    rows = []
    for line in open(path):
        parts = line.split()
        if len(parts) < 10 or parts[0] == "mesh":
            continue
        try:
            memory, rmse = float(parts[4]), float(parts[6])
        except ValueError:
            continue  # the original's row has '-' for the errors
        name = parts[0]
        series = name.rsplit("_", 1)[0] if "_" in name else name
        rows.append((series, name, memory, rmse))
    return rows


def series_points(rows):
    """[(series, [(memory, rmse), ...] sorted by memory)] in the order the series first appear."""
    order = []
    for r in rows:
        if r[0] not in order:
            order.append(r[0])
    return [(name, sorted((r[2], r[3]) for r in rows if r[0] == name)) for name in order]


def output_paths(out):
    """OUT.svg and OUT.png, whichever of the two (or neither) extension OUT has."""
    stem, extension = os.path.splitext(out)
    if extension.lower() not in (".svg", ".png"):
        stem = out
    return stem + ".svg", stem + ".png"


def plot_with_matplotlib(series, title, paths):
    import matplotlib

    matplotlib.use("Agg")  # no display: the main job runs headless
    matplotlib.rcParams["svg.fonttype"] = "none"  # SVG text stays text (searchable, smaller)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    for k, (name, points) in enumerate(series):
        ax.plot([p[0] for p in points], [p[1] for p in points], "-o", color=COLOURS[k % len(COLOURS)],
                label=name, linewidth=2, markersize=5)
    ax.set_title(title)
    ax.set_xlabel(X_LABEL)
    ax.set_ylabel(Y_LABEL)
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=9)
    fig.tight_layout()
    for path in paths:
        fig.savefig(path, dpi=100)
    plt.close(fig)


def write_plain_svg(series, title, path):
    """The fallback without matplotlib: lines and points on a grid, written as SVG text."""
    width, height, left, right, top, bottom = 720, 460, 80, 200, 40, 60
    xmax = max(p[0] for _, points in series for p in points) * 1.08
    ymax = max(p[1] for _, points in series for p in points) * 1.1
    sx = lambda x: left + (width - left - right) * x / xmax
    sy = lambda y: height - bottom - (height - top - bottom) * y / ymax
    svg = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">'
           % (width, height), '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="22" font-size="14">%s</text>' % (left, title)]
    for i in range(6):  # grid and ticks
        x, y = xmax * i / 5, ymax * i / 5
        svg.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#ddd"/>' % (sx(x), top, sx(x), height - bottom))
        svg.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#ddd"/>' % (left, sy(y), width - right, sy(y)))
        svg.append('<text x="%.1f" y="%d" text-anchor="middle">%.2f</text>' % (sx(x), height - bottom + 16, x))
        svg.append('<text x="%d" y="%.1f" text-anchor="end">%.4f</text>' % (left - 6, sy(y) + 4, y))
    svg.append('<text x="%.1f" y="%d" text-anchor="middle">%s</text>' % ((left + width - right) / 2, height - 18, X_LABEL))
    svg.append('<text x="18" y="%.1f" transform="rotate(-90 18 %.1f)" text-anchor="middle">%s</text>'
               % ((top + height - bottom) / 2, (top + height - bottom) / 2, Y_LABEL))
    for k, (name, points) in enumerate(series):
        colour = COLOURS[k % len(COLOURS)]
        svg.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>'
                   % (colour, " ".join("%.1f,%.1f" % (sx(x), sy(y)) for x, y in points)))
        for x, y in points:
            svg.append('<circle cx="%.1f" cy="%.1f" r="4" fill="%s"/>' % (sx(x), sy(y), colour))
        ly = top + 20 + 20 * k
        svg.append('<rect x="%d" y="%d" width="14" height="4" fill="%s"/>' % (width - right + 16, ly - 6, colour))
        svg.append('<text x="%d" y="%d">%s</text>' % (width - right + 36, ly, name))
    svg.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(svg) + "\n")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    table, out = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else "image error against memory"
    rows = read_rows(table)
    if not rows:
        sys.exit("no rows in " + table)
    series = series_points(rows)
    svg, png = output_paths(out)
    try:
        plot_with_matplotlib(series, title, [svg, png])
        print(f"plot: {svg}, {png}")
    except ImportError:
        sys.stderr.write("plot_error_vs_memory.py: matplotlib is missing, so no PNG and a plain SVG: install it "
                         "with 'pip install matplotlib' (or the package's extra: pip install '.[plots]')\n")
        write_plain_svg(series, title, svg)
        print(f"plot: {svg}")


if __name__ == "__main__":
    main()
