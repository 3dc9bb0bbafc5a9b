"""Checks of a baked normal-map file set without third-party modules (PNG decoded with zlib).

usage: check_baked_maps.py complete NORMAL_PNG      every texel decodes to a unit vector (no empty
                                                     texel anywhere: charts, gutters, background)
       check_baked_maps.py sphere OBJ NORMAL_PNG MAX_MEAN_DEG
                                                     object-space map of a mesh approximating the
                                                     unit sphere: at every texel centre inside a face
                                                     (barycentric test in UV), the decoded normal vs
                                                     the exact sphere normal where the ray from the
                                                     surface point along the interpolated normal
                                                     meets the unit sphere. Mean angle <= bound.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import png_reader  # noqa: E402


def read_png(path):
    """RGB normal map -> (width, height, texel(column, row) decoded to [-1, 1]^3)."""
    try:
        png = png_reader.read_png(path)
    except png_reader.PngError as error:
        raise SystemExit(str(error))
    if png.channels != 3:
        raise SystemExit(f"{path}: expected RGB, got {png.channels} channels")
    top = 65535.0 if png.depth == 16 else 255.0

    def texel(column, row):
        return [2.0 * png.sample(column, row, k) / top - 1.0 for k in range(3)]

    return png.width, png.height, texel


def read_obj(path):
    positions, normals, uvs, faces = [], [], [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            positions.append(tuple(map(float, parts[1:4])))
        elif parts[0] == "vn":
            normals.append(tuple(map(float, parts[1:4])))
        elif parts[0] == "vt":
            uvs.append(tuple(map(float, parts[1:3])))
        elif parts[0] == "f":
            corners = [c.split("/") for c in parts[1:]]
            for k in range(1, len(corners) - 1):
                faces.append([corners[0], corners[k], corners[k + 1]])
    return positions, normals, uvs, faces


def normalize(v):
    length = math.sqrt(sum(x * x for x in v))
    return [x / length for x in v] if length > 0 else v


def check_complete(png):
    width, height, texel = read_png(png)
    bad = 0
    for row in range(height):
        for column in range(width):
            n = texel(column, row)
            if abs(math.sqrt(sum(x * x for x in n)) - 1.0) > 0.02:
                bad += 1
    print(f"{width}x{height}: {bad} texels not a unit normal")
    return bad == 0


def check_sphere(obj, png, bound):
    positions, normals, uvs, faces = read_obj(obj)
    width, height, texel = read_png(png)
    total, count, worst = 0.0, 0, 0.0
    for face in faces:
        p = [positions[int(c[0]) - 1] for c in face]
        t = [uvs[int(c[1]) - 1] for c in face]
        # Vertex normals: the OBJ's when present, else the unit sphere's (radial).
        n = [normals[int(c[2]) - 1] if len(c) > 2 and c[2] else normalize(q) for c, q in zip(face, p)]
        x = [u * width for u, _ in t]
        y = [(1.0 - v) * height for _, v in t]
        area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
        if abs(area) < 1e-9:
            continue
        for row in range(max(0, int(min(y))), min(height, int(max(y)) + 1)):
            for column in range(max(0, int(min(x))), min(width, int(max(x)) + 1)):
                cx, cy = column + 0.5, row + 0.5
                b1 = ((cx - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (cy - y[0])) / area
                b2 = ((x[1] - x[0]) * (cy - y[0]) - (cx - x[0]) * (y[1] - y[0])) / area
                b0 = 1.0 - b1 - b2
                if min(b0, b1, b2) < 0.0:
                    continue
                point = [b0 * p[0][k] + b1 * p[1][k] + b2 * p[2][k] for k in range(3)]
                d = normalize([b0 * n[0][k] + b1 * n[1][k] + b2 * n[2][k] for k in range(3)])
                # |point + s d| = 1: s^2 + 2 (point.d) s + |point|^2 - 1 = 0, the root nearest 0.
                pd = sum(point[k] * d[k] for k in range(3))
                pp = sum(point[k] * point[k] for k in range(3))
                s = -pd + math.sqrt(max(pd * pd - pp + 1.0, 0.0))
                exact = normalize([point[k] + s * d[k] for k in range(3)])
                baked = normalize(texel(column, row))
                angle = math.degrees(math.acos(max(-1.0, min(1.0, sum(exact[k] * baked[k] for k in range(3))))))
                total += angle
                count += 1
                worst = max(worst, angle)
    mean = total / max(count, 1)
    print(f"{count} texels inside faces: mean {mean:.4f} deg, max {worst:.4f} deg (bound on the mean {bound})")
    return count > 0 and mean <= bound


if __name__ == "__main__":
    if sys.argv[1] == "complete":
        ok = check_complete(sys.argv[2])
    elif sys.argv[1] == "sphere":
        ok = check_sphere(sys.argv[2], sys.argv[3], float(sys.argv[4]))
    else:
        raise SystemExit(__doc__)
    sys.exit(0 if ok else 1)
