#!/usr/bin/env python3
"""plot_error_vs_memory.py TABLE.txt OUT.svg [TITLE]: the image error against memory plot of the main
job, from the table compare_radiance_meshes prints. A row's series is its name up to the last '_'
(e.g. 'radiance_250' -> 'radiance'); the original (no error) is skipped. Plain SVG, no dependencies."""
import sys

COLOURS = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]


def read_rows(path):
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


def main():
    table, out = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else "image error against memory"
    rows = read_rows(table)
    if not rows:
        sys.exit("no rows in " + table)
    width, height, left, right, top, bottom = 720, 460, 80, 200, 40, 60
    xmax = max(r[2] for r in rows) * 1.08
    ymax = max(r[3] for r in rows) * 1.1
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
    svg.append('<text x="%.1f" y="%d" text-anchor="middle">memory (MB)</text>' % ((left + width - right) / 2, height - 18))
    svg.append('<text x="18" y="%.1f" transform="rotate(-90 18 %.1f)" text-anchor="middle">mean image RMSE (linear)</text>'
               % ((top + height - bottom) / 2, (top + height - bottom) / 2))
    series = []
    for r in rows:
        if r[0] not in series:
            series.append(r[0])
    for k, name in enumerate(series):
        colour = COLOURS[k % len(COLOURS)]
        points = sorted((r[2], r[3]) for r in rows if r[0] == name)
        svg.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>'
                   % (colour, " ".join("%.1f,%.1f" % (sx(x), sy(y)) for x, y in points)))
        for x, y in points:
            svg.append('<circle cx="%.1f" cy="%.1f" r="4" fill="%s"/>' % (sx(x), sy(y), colour))
        ly = top + 20 + 20 * k
        svg.append('<rect x="%d" y="%d" width="14" height="4" fill="%s"/>' % (width - right + 16, ly - 6, colour))
        svg.append('<text x="%d" y="%d">%s</text>' % (width - right + 36, ly, name))
    svg.append("</svg>")
    open(out, "w").write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()
