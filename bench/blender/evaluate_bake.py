"""Angular error of a tangent-space normal map against the exact normals of the analytic surface
(bench/bake_vs_blender.sh). Every texel whose centre lies inside a UV triangle of the low mesh is
decoded the MikkTSpace way (Mikkelsen 2008): T and N interpolated from the corners (Blender's
tangents, equal to ours within 1e-6: tests/blender), B = sign N x T, n = normalize(x T + y B + z N);
the truth is the exact surface's normal where the ray from the texel's point along +/- N meets it
(the nearer hit), which is what both bakers aim at.

Usage: evaluate_bake.py sphere|torus LOW.corners MAP(.png 8/16 bit or .npy float, rows top to bottom)
Prints: texels, mean, median, p95, max in degrees.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tests", "integration"))
import png_reader  # noqa: E402

R, r = 1.0, 0.35


def read_map(path):
    if path.endswith(".npy"):
        return np.load(path).astype(np.float64)
    png = png_reader.read_png(path)
    dtype = ">u2" if png.depth == 16 else "u1"
    rows = [np.frombuffer(bytes(row), dtype=dtype, count=png.width * png.channels) for row in png.rows]
    array = np.stack(rows).reshape(png.height, png.width, png.channels)[:, :, :3].astype(np.float64)
    return array / (65535.0 if png.depth == 16 else 255.0)


def torus_sdf(q):
    return np.hypot(np.hypot(q[:, 0], q[:, 1]) - R, q[:, 2]) - r


def torus_normal(q):
    ring = q.copy()
    ring[:, 2] = 0
    ring = R * ring / np.linalg.norm(ring, axis=1, keepdims=True)
    d = q - ring
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def exact_normal(shape, p, n):
    if shape == "sphere":
        b = (p * n).sum(1)
        c = (p * p).sum(1) - 1
        root = np.sqrt(np.maximum(b * b - c, 0))
        t1, t2 = -b + root, -b - root
        t = np.where(np.abs(t1) < np.abs(t2), t1, t2)
        q = p + t[:, None] * n
        return q / np.linalg.norm(q, axis=1, keepdims=True)
    t = np.zeros(len(p))
    for _ in range(30):  # Newton on the signed distance along the ray, from the low surface
        q = p + t[:, None] * n
        t -= torus_sdf(q) / np.maximum((torus_normal(q) * n).sum(1), 1e-6)
    return torus_normal(p + t[:, None] * n)


def main():
    shape, corners_path, map_path = sys.argv[1:4]
    c = np.loadtxt(corners_path).reshape(-1, 3, 12)
    image = read_map(map_path) * 2 - 1
    size = image.shape[0]
    errors = []
    for face in c:
        pos, nor, uv, tan, sign = face[:, 0:3], face[:, 3:6], face[:, 6:8], face[:, 8:11], face[0, 11]
        x = uv[:, 0] * size
        y = (1.0 - uv[:, 1]) * size
        area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
        if abs(area) < 1e-9:
            continue
        cols = np.arange(max(0, int(x.min())), min(size, int(x.max()) + 1))
        rows = np.arange(max(0, int(y.min())), min(size, int(y.max()) + 1))
        cc, rr = np.meshgrid(cols, rows)
        cc, rr = cc.ravel(), rr.ravel()
        cx, cy = cc + 0.5, rr + 0.5
        b1 = ((cx - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (cy - y[0])) / area
        b2 = ((x[1] - x[0]) * (cy - y[0]) - (cx - x[0]) * (y[1] - y[0])) / area
        b0 = 1 - b1 - b2
        inside = (b0 >= 0) & (b1 >= 0) & (b2 >= 0)
        if not inside.any():
            continue
        w = np.stack([b0, b1, b2], 1)[inside]
        p, n, t = w @ pos, w @ nor, w @ tan
        b = sign * np.cross(n, t)
        code = image[rr[inside], cc[inside]]
        decoded = code[:, :1] * t + code[:, 1:2] * b + code[:, 2:3] * n
        decoded /= np.linalg.norm(decoded, axis=1, keepdims=True)
        truth = exact_normal(shape, p, n / np.linalg.norm(n, axis=1, keepdims=True))
        errors.append(np.degrees(np.arctan2(np.linalg.norm(np.cross(decoded, truth), axis=1), (decoded * truth).sum(1))))
    e = np.concatenate(errors)
    print("texels %d mean %.4f median %.4f p95 %.4f max %.3f" % (e.size, e.mean(), np.median(e), np.percentile(e, 95), e.max()))


if __name__ == "__main__":
    main()
