#!/usr/bin/env python3
"""Independent check of radiance functions fitted from photographs (through meshlabserver): the
fitted RF of a vertex, evaluated toward a camera, must reproduce what that camera's photograph
shows at the vertex's projection.

Everything here is written independently of the C++ code under test: the MeshLab project (.mlp)
camera model is implemented from the platform notes (docs: RotationMatrix rows = camera right, up,
backwards; TranslationVector = -C; px from the left, py from the bottom), PNG decoding is a small
zlib-based reader, the PB basis is evaluated from its definition (u^i v^j in the vertex's tangent
frame, ordered by total degree then by j). Meant for convex scenes (no occlusion test here).

  check_fit_against_photos.py FIT.rply PROJECT.mlp MEDIAN_MAX P90_MAX [MIN_COS]
      errors in 8-bit sRGB levels over (vertex, view) pairs with n.w >= MIN_COS (default 0.5)
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ply_reader  # noqa: E402
import png_reader  # noqa: E402


def fail(message):
    print("check_fit_against_photos: FAIL: " + message)
    sys.exit(1)


def read_png_rgb(path):
    """8-bit RGB / RGBA PNG -> (width, height, rows of [r, g, b, ...])."""
    try:
        png = png_reader.read_png(path)
    except png_reader.PngError as error:
        fail(str(error))
    if png.depth != 8:
        fail(f"{path}: unsupported PNG (depth {png.depth})")
    rows = [[row[x * png.channels + k] for x in range(png.width) for k in range(3)] for row in png.rows]
    return png.width, png.height, rows


def srgb_decode(code):
    s = code / 255.0
    return s / 12.92 if s <= 0.04045 else ((s + 0.055) / 1.055) ** 2.4


def srgb_encode(x):
    x = min(max(x, 0.0), 1.0)
    return 255.0 * (12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055)


def read_project(path):
    cameras = []
    root = ET.parse(path).getroot()
    for raster in root.iter("MLRaster"):
        cam = raster.find("VCGCamera")
        plane = raster.find("Plane")
        nums = lambda key: [float(x) for x in cam.get(key).split()]
        rot = nums("RotationMatrix")
        cameras.append({
            "rows": [rot[0:3], rot[4:7], rot[8:11]],
            "centre": [-x for x in nums("TranslationVector")[:3]],
            "focal": float(cam.get("FocalMm")),
            "pixel": nums("PixelSizeMm"),
            "centre_px": nums("CenterPx"),
            "viewport": [int(x) for x in cam.get("ViewportPx").split()],
            "image": os.path.join(os.path.dirname(path), plane.get("fileName")),
        })
    return cameras


def project(cam, x):
    d = [x[i] - cam["centre"][i] for i in range(3)]
    cp = [sum(cam["rows"][r][i] * d[i] for i in range(3)) for r in range(3)]
    depth = -cp[2]
    if depth <= 0:
        return None
    px = cp[0] * cam["focal"] / depth / cam["pixel"][0] + cam["centre_px"][0]
    py = cp[1] * cam["focal"] / depth / cam["pixel"][1] + cam["centre_px"][1]
    return px, py


def bilinear(image, px, py):
    width, height, rows = image
    # Pixel (c, r from the top) is centred at px = c + 0.5, py = H - r - 0.5.
    x = px - 0.5
    y = (height - py) - 0.5
    if x < 1 or y < 1 or x > width - 2 or y > height - 2:
        return None
    x0, y0 = int(x), int(y)
    fx, fy = x - x0, y - y0
    out = []
    for c in range(3):
        v00 = srgb_decode(rows[y0][3 * x0 + c])
        v10 = srgb_decode(rows[y0][3 * (x0 + 1) + c])
        v01 = srgb_decode(rows[y0 + 1][3 * x0 + c])
        v11 = srgb_decode(rows[y0 + 1][3 * (x0 + 1) + c])
        out.append((v00 * (1 - fx) + v10 * fx) * (1 - fy) + (v01 * (1 - fx) + v11 * fx) * fy)
    return out


def pb_exponents(degree):
    return [(total - j, j) for total in range(degree + 1) for j in range(total + 1)]


def main():
    if len(sys.argv) < 5:
        print(__doc__)
        sys.exit(2)
    fit_path, project_path = sys.argv[1], sys.argv[2]
    median_max, p90_max = float(sys.argv[3]), float(sys.argv[4])
    min_cos = float(sys.argv[5]) if len(sys.argv) > 5 else 0.5
    ply = ply_reader.read_ply(fit_path)
    meta = {}
    for line in ply["comments"]:
        parts = line.split(None, 1)
        if len(parts) == 2:
            meta[parts[0]] = parts[1].strip()
    basis = meta.get("radiance_basis", "")
    if not basis.startswith("PB") or meta.get("radiance_reflected") != "0":
        fail(f"this checker evaluates plain PB functions only, the file holds {basis} reflected={meta.get('radiance_reflected')}")
    exponents = pb_exponents(int(basis[2:]))
    vertex = ply["elements"]["vertex"]
    cameras = read_project(project_path)
    images = [read_png_rgb(c["image"]) for c in cameras]
    count = len(vertex["x"])
    errors = []
    step = max(1, count // 1500)
    for v in range(0, count, step):
        p = [vertex["x"][v], vertex["y"][v], vertex["z"][v]]
        n = [vertex["nx"][v], vertex["ny"][v], vertex["nz"][v]]
        t = [vertex["rf_tx"][v], vertex["rf_ty"][v], vertex["rf_tz"][v]]
        b = [n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]]
        for cam, image in zip(cameras, images):
            w = [cam["centre"][i] - p[i] for i in range(3)]
            length = math.sqrt(sum(x * x for x in w))
            w = [x / length for x in w]
            if sum(a * c for a, c in zip(n, w)) < min_cos:
                continue
            pixel = project(cam, p)
            if pixel is None:
                continue
            seen = bilinear(image, *pixel)
            if seen is None:
                continue
            u = sum(a * c for a, c in zip(t, w))
            vv = sum(a * c for a, c in zip(b, w))
            basis_values = [u ** i * vv ** j for i, j in exponents]
            for ci, c in enumerate("rgb"):
                value = sum(vertex[f"rf_{c}_{k}"][v] * basis_values[k] for k in range(len(exponents)))
                errors.append(abs(srgb_encode(value) - srgb_encode(seen[ci])))
    if len(errors) < 300:
        fail(f"only {len(errors)} vertex-view comparisons: the cameras do not see the mesh?")
    errors.sort()
    median = errors[len(errors) // 2]
    p90 = errors[int(0.9 * len(errors))]
    print(f"fit vs photos: {len(errors)} comparisons, median {median:.2f}, 90th percentile {p90:.2f}, "
          f"max {errors[-1]:.2f} sRGB levels")
    if median > median_max or p90 > p90_max:
        fail(f"median {median:.2f} > {median_max} or 90th percentile {p90:.2f} > {p90_max}")


if __name__ == "__main__":
    main()
