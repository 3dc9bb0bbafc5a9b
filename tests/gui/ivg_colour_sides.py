#!/usr/bin/env python3
"""ivg_colour_sides.py IMAGE X Y W H

In the crop (X, Y, W, H) of IMAGE, counts the pixels of red hue and of green hue (saturated, not dark)
and prints "red COUNT MEAN_X green COUNT MEAN_X" (MEAN_X the mean column in the crop, -1 when none),
for the GUI test of the "Irradiance Vector Grid" decoration (red light from +x, green from -x; MeshLab's background is blue)."""
import colorsys
import sys
import os

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from count_colour_pixels import read_ppm  # noqa: E402


def main():
    path = sys.argv[1]
    x0, y0, w, h = (int(v) for v in sys.argv[2:6])
    width, height, pixels = read_ppm(path)
    counts = {"red": [0, 0], "green": [0, 0]}
    for y in range(y0, min(height, y0 + h)):
        for x in range(x0, min(width, x0 + w)):
            i = 3 * (y * width + x)
            hue, s, v = colorsys.rgb_to_hsv(pixels[i] / 255, pixels[i + 1] / 255, pixels[i + 2] / 255)
            if v < 0.15 or s < 0.5:
                continue
            if hue < 0.04 or hue > 0.96:
                counts["red"][0] += 1
                counts["red"][1] += x - x0
            elif abs(hue - 1 / 3) < 0.04:
                counts["green"][0] += 1
                counts["green"][1] += x - x0
    out = []
    for name in ("red", "green"):
        n, sx = counts[name]
        out.append(f"{name} {n} {sx / n if n else -1:.1f}")
    print(" ".join(out))


if __name__ == "__main__":
    main()
