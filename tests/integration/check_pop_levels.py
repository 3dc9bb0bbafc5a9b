#!/usr/bin/env python3
"""Input and checks of test_pop_buffer_levels.sh (pure Python, no code shared with the C++).

  check_pop_levels.py make OUT.ply          a tilted textured plane, ASCII PLY with wedge texcoords
  check_pop_levels.py check LAYER.ply LEVEL  a level written by "Extract Level of Detail (POP Buffer)"

The expected values follow the definitions: Limper et al. 2013's grid of 2^L cells per axis over the
input's bounding box (vertices at cell centres; a triangle kept when its corners are in three
different cells) and Weber & Stamminger's Alg. 1, exact on a plane with linear texture coordinates
(the corrected coordinates are the plane's map at the orthogonal projection of the snapped vertex).
"""
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ply_reader import read_ply  # noqa: E402

# p = ORIGIN + s A + t B, uv = M (s, t) + O, with A and B orthogonal (projection = dot products).
ORIGIN = (0.2, -0.4, 1.0)
A = (2.0, 0.0, 1.0)
B = (-0.5, 1.5, 1.0)
M = ((0.6, 0.2), (-0.1, 0.5))
O = (0.1, 0.3)
N = 16


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def mesh():
    rng = random.Random(9)
    st = []
    for j in range(N):
        for i in range(N):
            inner = 0 < i < N - 1 and 0 < j < N - 1
            st.append(((i + (rng.uniform(-0.3, 0.3) if inner else 0)) / (N - 1),
                       (j + (rng.uniform(-0.3, 0.3) if inner else 0)) / (N - 1)))
    points = [tuple(ORIGIN[k] + s * A[k] + t * B[k] for k in range(3)) for s, t in st]
    faces = []
    for j in range(N - 1):
        for i in range(N - 1):
            a, b, c, d = j * N + i, j * N + i + 1, (j + 1) * N + i + 1, (j + 1) * N + i
            faces += [(a, b, c), (a, c, d)]
    return points, faces


def uv_at(p):
    rel = [p[k] - ORIGIN[k] for k in range(3)]
    s, t = dot(rel, A) / dot(A, A), dot(rel, B) / dot(B, B)
    return (M[0][0] * s + M[0][1] * t + O[0], M[1][0] * s + M[1][1] * t + O[1])


def make(path):
    points, faces = mesh()
    # Written as text with 9 significant digits: the checks use the float32 values MeshLab reads.
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(points))
        f.write("property float x\nproperty float y\nproperty float z\n")
        f.write("element face %d\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n"
                "end_header\n" % len(faces))
        for p in points:
            f.write("%.9g %.9g %.9g\n" % p)
        for t in faces:
            uv = [c for v in t for c in uv_at(points[v])]
            f.write("3 %d %d %d 6 %s\n" % (t + (" ".join("%.9g" % c for c in uv),)))


def fail(message):
    print("check_pop_levels: " + message, file=sys.stderr)
    sys.exit(1)


def check(path, level):
    points, faces = mesh()
    import struct
    points = [tuple(struct.unpack("f", struct.pack("f", float("%.9g" % c)))[0] for c in p) for p in points]
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    cells = 2 ** level

    def cell(p):
        return tuple(min(math.floor((p[k] - lo[k]) / (hi[k] - lo[k]) * cells), cells - 1) for k in range(3))

    kept = 0
    for t in faces:
        c = [cell(points[v]) for v in t]
        kept += c[0] != c[1] and c[1] != c[2] and c[0] != c[2]
    ply = read_ply(path)
    xs, ys, zs = (ply.data["vertex"][k] for k in "xyz")
    layer_faces = ply.data["face"]["vertex_indices"]
    texcoords = ply.data["face"]["texcoord"]
    if len(layer_faces) != kept:
        fail(f"level {level}: {len(layer_faces)} faces, expected {kept} non-degenerate triangles")
    if not 0 < kept < len(faces):
        fail(f"level {level}: a level that keeps {kept} of {len(faces)} triangles tests nothing")
    for v, p in enumerate(zip(xs, ys, zs)):
        for k in range(3):
            index = (p[k] - lo[k]) / ((hi[k] - lo[k]) / cells) - 0.5
            if abs(index - round(index)) > 1e-4 or not -1e-4 < index < cells - 1 + 1e-4:
                fail(f"level {level}: vertex {v} coordinate {k} = {p[k]} is not a cell centre (index {index})")
    worst = 0.0
    for f, (t, uv) in enumerate(zip(layer_faces, texcoords)):
        for k, v in enumerate(t):
            expected = uv_at((xs[v], ys[v], zs[v]))
            worst = max(worst, abs(uv[2 * k] - expected[0]), abs(uv[2 * k + 1] - expected[1]))
    if worst > 1e-4:
        fail(f"level {level}: corrected texture coordinates off the plane's map by {worst}")
    print(f"level {level}: {kept} faces, {len(xs)} vertices on the grid, texture error {worst:.2e}")


if __name__ == "__main__":
    if sys.argv[1] == "make":
        make(sys.argv[2])
    else:
        check(sys.argv[2], int(sys.argv[3]))
