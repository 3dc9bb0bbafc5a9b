#!/usr/bin/env python3
"""count_colour_pixels.py IMAGE R G B MIN_COUNT

Counts pixels whose hue is close to the colour (R, G, B) (0-255), whatever their shading, and
exits 1 when there are fewer than MIN_COUNT. The image is converted to plain PPM with ImageMagick's
`convert` so no Python imaging package is needed."""
import colorsys
import subprocess
import sys


def read_ppm(path):
    data = subprocess.run(["convert", path, "-depth", "8", "ppm:-"], check=True,
                          stdout=subprocess.PIPE).stdout
    # P6 header: magic, width, height, maxval separated by whitespace.
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos])
    pos += 1
    width, height = int(fields[1]), int(fields[2])
    return width, height, data[pos:pos + 3 * width * height]


def main():
    path, r, g, b, minimum = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
    target_h, target_s, _ = colorsys.rgb_to_hsv(r / 255, g / 255, b / 255)
    width, height, pixels = read_ppm(path)
    count = 0
    for i in range(0, len(pixels), 3):
        h, s, v = colorsys.rgb_to_hsv(pixels[i] / 255, pixels[i + 1] / 255, pixels[i + 2] / 255)
        hue_distance = min(abs(h - target_h), 1 - abs(h - target_h))
        if v > 0.08 and s > 0.5 * target_s and hue_distance < 0.04:
            count += 1
    print(f"{count} of {width * height} pixels have the mesh's hue")
    sys.exit(0 if count >= minimum else 1)


if __name__ == "__main__":
    main()
