#!/usr/bin/env python3
"""Independent checks of a simplified radiance mesh against its original, with the stand-alone
pure-Python PLY reader (ply_reader.py), not the C++ code under test.

  check_simplification.py halfedge ORIGINAL SIMPLIFIED MAX_FACES MIN_FACES
      SIMPLIFIED is a closed, consistently oriented 2-manifold of genus 0 with MIN..MAX faces; every
      vertex is an original vertex (half-edge collapses never move one) and carries exactly that
      vertex's radiance properties (the functions followed their vertices).
  check_simplification.py samefaces A B
      A and B have the same faces, as sets of position triples (vertex numbering may differ).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ply_reader  # noqa: E402


def fail(message):
    print("check_simplification: " + message, file=sys.stderr)
    sys.exit(1)


def load(path):
    ply = ply_reader.read_ply(path)
    v = ply.data["vertex"]
    n = len(v["x"])
    positions = [(v["x"][i], v["y"][i], v["z"][i]) for i in range(n)]
    rf_names = sorted(name for name in v if name.startswith("rf_"))
    rows = [tuple(v[name][i] for name in rf_names) for i in range(n)]
    faces = [tuple(f) for f in ply.data["face"]["vertex_indices"]]
    return positions, rf_names, rows, faces


def face_triples(positions, faces):
    out = set()
    for f in faces:
        corners = [positions[i] for i in f]
        k = corners.index(min(corners))
        out.add(tuple(corners[k:] + corners[:k]))  # rotation keeps the orientation
    return out


def check_halfedge(original, simplified, max_faces, min_faces):
    p0, names0, rows0, _ = load(original)
    p1, names1, rows1, faces = load(simplified)
    if not (min_faces <= len(faces) <= max_faces):
        fail("%s has %d faces, expected %d..%d" % (simplified, len(faces), min_faces, max_faces))
    if names0 != names1 or not names1:
        fail("radiance properties differ or are missing: %s vs %s" % (names0[:4], names1[:4]))
    directed = {}
    for f in faces:
        if len(f) != 3 or len(set(f)) != 3:
            fail("face %s is not a proper triangle" % (f,))
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            directed[(a, b)] = directed.get((a, b), 0) + 1
    for (a, b), count in directed.items():
        if count != 1:
            fail("directed edge %d->%d used %d times (non-manifold or flipped face)" % (a, b, count))
        if (b, a) not in directed:
            fail("edge %d-%d has one face only: the surface is no longer closed" % (a, b))
    used = {i for f in faces for i in f}
    euler = len(used) - len(directed) // 2 + len(faces)
    if euler != 2:
        fail("Euler characteristic %d, expected 2 (the sphere's topology changed)" % euler)
    where = {p: i for i, p in enumerate(p0)}
    for i, p in enumerate(p1):
        j = where.get(p)
        if j is None:
            fail("vertex %d at %s is not an original vertex" % (i, p))
        if rows1[i] != rows0[j]:
            fail("vertex %d carries other radiance data than original vertex %d at the same position" % (i, j))
    print("ok: %d faces, %d vertices, closed oriented genus-0 manifold, vertices and radiance rows are the "
          "original's" % (len(faces), len(p1)))


def check_same_faces(a, b):
    pa, _, _, fa = load(a)
    pb, _, _, fb = load(b)
    ta, tb = face_triples(pa, fa), face_triples(pb, fb)
    if ta != tb:
        fail("%s and %s differ: %d faces only in the first, %d only in the second"
             % (a, b, len(ta - tb), len(tb - ta)))
    print("ok: the same %d faces" % len(ta))


def main():
    mode = sys.argv[1]
    if mode == "halfedge":
        check_halfedge(sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5]))
    elif mode == "samefaces":
        check_same_faces(sys.argv[2], sys.argv[3])
    else:
        fail("unknown mode " + mode)


if __name__ == "__main__":
    main()
