"""Angular error of a baked normal map (bench/bake_vs_blender.sh). Every texel whose centre lies
inside a UV triangle of the low mesh is decoded: in tangent space the MikkTSpace way (Mikkelsen
2008): T and N interpolated from the corners (Blender's tangents, equal to ours within 1e-6:
tests/blender), B = sign N x T, n = normalize(x T + y B + z N); in object space n = normalize(x, y, z).
The truth:
  sphere, torus   the exact surface's normal where the ray from the texel's point along +/- N meets
                  it (the nearer hit), which is what both bakers aim at;
  reference       a table made by scan_reference.py (a real scan: the high mesh's interpolated normal
                  where the texel's ray meets it, found by Blender's BVH tree, neither baker's code).

Usage: evaluate_bake.py sphere|torus tangent|object LOW.corners MAP
       evaluate_bake.py reference:REF.npz tangent|object LOW.corners MAP    (nearest-hit rule)
       evaluate_bake.py reference-cage:REF.npz tangent|object LOW.corners MAP   (Cycles' cage rule)
       evaluate_bake.py agree tangent|object LOW.corners MAP1 MAP2     (angle between two maps)
MAP: .png 8/16 bit or .npy float, rows top to bottom, code = (n + 1) / 2.
Prints: texels, mean, median, p95, max in degrees.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "integration"))
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


def chart_texels(corners_path, size, stride=1):
    """The texels whose centre is inside a UV triangle (rows and columns multiples of `stride`):
    rows, cols, and per texel the interpolated point p, normal n (not normalised), tangent t and sign."""
    c = np.loadtxt(corners_path).reshape(-1, 3, 12)
    out = {k: [] for k in ("rows", "cols", "p", "n", "t", "sign")}
    for face in c:
        pos, nor, uv, tan, sign = face[:, 0:3], face[:, 3:6], face[:, 6:8], face[:, 8:11], face[0, 11]
        x = uv[:, 0] * size
        y = (1.0 - uv[:, 1]) * size
        area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
        if abs(area) < 1e-9:
            continue
        c0, r0 = max(0, int(x.min())), max(0, int(y.min()))
        cols = np.arange(c0 + (-c0) % stride, min(size, int(x.max()) + 1), stride)
        rows = np.arange(r0 + (-r0) % stride, min(size, int(y.max()) + 1), stride)
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
        out["rows"].append(rr[inside])
        out["cols"].append(cc[inside])
        out["p"].append(w @ pos)
        out["n"].append(w @ nor)
        out["t"].append(w @ tan)
        out["sign"].append(np.full(int(inside.sum()), sign))
    return {k: np.concatenate(v) for k, v in out.items()}


def decode(image, texels, space):
    code = image[texels["rows"], texels["cols"]] * 2 - 1
    if space == "object":
        decoded = code
    else:
        n, t = texels["n"], texels["t"]
        b = texels["sign"][:, None] * np.cross(n, t)
        decoded = code[:, :1] * t + code[:, 1:2] * b + code[:, 2:3] * n
    return decoded / np.linalg.norm(decoded, axis=1, keepdims=True)


def angles(a, b):
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(1)))


def main():
    truth_kind, space, corners_path = sys.argv[1:4]
    assert space in ("tangent", "object"), space
    image = read_map(sys.argv[4])
    size = image.shape[0]
    texels = chart_texels(corners_path, size)
    decoded = decode(image, texels, space)
    if truth_kind == "agree":
        e = angles(decoded, decode(read_map(sys.argv[5]), texels, space))
    elif truth_kind.startswith("reference"):
        ref = np.load(truth_kind.split(":", 1)[1])
        assert int(ref["size"]) == size, "the reference was made for %d^2 texels" % int(ref["size"])
        keys = texels["rows"].astype(np.int64) * size + texels["cols"]
        order = np.argsort(keys)
        where = order[np.searchsorted(keys[order], ref["rows"].astype(np.int64) * size + ref["cols"])]
        e = angles(decoded[where], ref["normals_cage" if truth_kind.startswith("reference-cage:") else "normals"])
    else:
        n = texels["n"] / np.linalg.norm(texels["n"], axis=1, keepdims=True)
        e = angles(decoded, exact_normal(truth_kind, texels["p"], n))
    print("texels %d mean %.4f median %.4f p95 %.4f max %.3f" % (e.size, e.mean(), np.median(e), np.percentile(e, 95), e.max()))


if __name__ == "__main__":
    main()
