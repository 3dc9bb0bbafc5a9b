#!/usr/bin/env python3
"""Independent checks of the PRT filters' outputs (pure Python, shares no code with the C++ cores).

  check_prt.py column-transfer FILE.rply [ORDER]   transfer block present, finite; ground vertices' band-0
                                                   coefficient = Y00 x the cosine-weighted visible fraction,
                                                   computed here by brute-force geometry against the column
  check_prt.py conforming FILE.rply MIN_FACES MAX_FACES
                                                   face count in range; every undirected edge (matched by
                                                   position) on at most two faces, consistently oriented; no
                                                   vertex strictly inside another face's edge (no T-junction);
                                                   total area equal to that of the column scene
  check_prt.py refined-near-column FILE.rply       ground faces near the column are smaller than far ones
  check_prt.py shadowed FILE.ply LX LY LZ          relit vertex colours: ground vertices in the column's
                                                   shadow are darker than lit ones
  check_prt.py face-quality FILE.ply               face quality present, finite, >= 0, not all equal
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ply_reader import read_ply  # noqa: E402

Y00 = 0.5 / math.sqrt(math.pi)
# make_scene column defaults (geometry/primitive_meshes.h): radius 0.15, height 1, ground [-1, 1]^2.
COLUMN_RADIUS, COLUMN_HEIGHT, GROUND_HALF = 0.15, 1.0, 1.0


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def positions(ply):
    v = ply.data['vertex']
    return list(zip(v['x'], v['y'], v['z']))


def transfer(ply, width):
    v = ply.data['vertex']
    names = ['prt_%d' % i for i in range(width)]
    for n in names:
        if n not in v:
            fail("no property %s: the transfer block is missing" % n)
    return [list(row) for row in zip(*(v[n] for n in names))]


def block_width(ply):
    for c in ply.comments:
        parts = c.split()
        if len(parts) == 4 and parts[0] == 'block' and parts[1] == 'prt' and parts[2] == 'width':
            return int(parts[3])
    fail("no 'comment block prt width N' in the header")


def ray_hits_column(p, d):
    """Whether the ray p + t d (t > 0) hits the closed cylinder of the column (axis z, base z = 0)."""
    ox, oy, oz = p
    dx, dy, dz = d
    a = dx * dx + dy * dy
    hits = []
    if a > 1e-12:
        b = 2 * (ox * dx + oy * dy)
        c = ox * ox + oy * oy - COLUMN_RADIUS ** 2
        disc = b * b - 4 * a * c
        if disc >= 0:
            for t in ((-b - math.sqrt(disc)) / (2 * a), (-b + math.sqrt(disc)) / (2 * a)):
                if t > 1e-6 and 0.0 <= oz + t * dz <= COLUMN_HEIGHT:
                    hits.append(t)
    if abs(dz) > 1e-12:
        t = (COLUMN_HEIGHT - oz) / dz
        if t > 1e-6 and (ox + t * dx) ** 2 + (oy + t * dy) ** 2 <= COLUMN_RADIUS ** 2:
            hits.append(t)
    return bool(hits)


def visible_fraction(p, samples=48):
    """Cosine-weighted visible fraction of the upper hemisphere at ground point p (midpoint rule in
    (u = sin^2 theta, phi), whose Jacobian makes the cosine weighting uniform)."""
    visible = 0
    total = 0
    for i in range(samples):
        u = (i + 0.5) / samples
        s = math.sqrt(u)
        z = math.sqrt(1 - u)
        for j in range(2 * samples):
            phi = 2 * math.pi * (j + 0.5) / (2 * samples)
            d = (s * math.cos(phi), s * math.sin(phi), z)
            total += 1
            if not ray_hits_column((p[0], p[1], p[2] + 1e-6), d):
                visible += 1
    return visible / total


def check_column_transfer(path):
    ply = read_ply(path)
    width = block_width(ply)
    t = transfer(ply, width)
    for row in t:
        if not all(math.isfinite(x) for x in row):
            fail("non-finite transfer coefficient")
    pts = positions(ply)
    nz = ply.data['vertex'].get('nz')
    ground = [i for i, p in enumerate(pts) if abs(p[2]) < 1e-6 and (nz is None or nz[i] > 0.9)
              and math.hypot(p[0], p[1]) > COLUMN_RADIUS + 1e-3]
    if len(ground) < 20:
        fail("too few ground vertices (%d)" % len(ground))
    # Every 3rd ground vertex (the brute force is slow in Python), the closest ones to the column first.
    ground.sort(key=lambda i: math.hypot(pts[i][0], pts[i][1]))
    worst = 0.0
    shadowed = 0
    for i in ground[:24] + ground[24::7]:
        expected = Y00 * visible_fraction(pts[i])
        worst = max(worst, abs(t[i][0] - expected))
        if expected < 0.97 * Y00:
            shadowed += 1
        # 256 low-discrepancy rays vs a 48 x 96 midpoint rule: a few percent of Y00.
        if abs(t[i][0] - expected) > 0.06 * Y00:
            fail("ground vertex %d at %s: t_0 = %.4f, brute-force geometry says %.4f"
                 % (i, pts[i], t[i][0], expected))
    if shadowed < 3:
        fail("only %d checked ground vertices are occluded by the column" % shadowed)
    print("column transfer: %d vertices, width %d; band 0 of %d ground vertices within %.4f of the geometric "
          "visible fraction (%d occluded)" % (len(pts), width, len(ground[:24] + ground[24::7]), worst, shadowed))


def edge_key(a, b):
    return (a, b) if a <= b else (b, a)


def check_conforming(path, min_faces, max_faces):
    ply = read_ply(path)
    pts = positions(ply)
    faces = ply.data['face']['vertex_indices']
    if not (min_faces <= len(faces) <= max_faces):
        fail("%d faces, expected %d..%d" % (len(faces), min_faces, max_faces))
    key = {}
    pos_id = []
    for p in pts:
        pos_id.append(key.setdefault(p, len(key)))
    directed = {}
    undirected = {}
    area = 0.0
    for f in faces:
        ids = [pos_id[i] for i in f]
        a, b, c = (pts[i] for i in f)
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        area += 0.5 * math.sqrt(sum(x * x for x in n))
        for k in range(3):
            e = (ids[k], ids[(k + 1) % 3])
            if e in directed:
                fail("directed edge %s used twice: inconsistent orientation" % (e,))
            directed[e] = True
            undirected[edge_key(*e)] = undirected.get(edge_key(*e), 0) + 1
    bad = [e for e, n in undirected.items() if n > 2]
    if bad:
        fail("%d edges on more than two faces" % len(bad))
    # T-junctions: a vertex strictly inside a boundary edge (an edge with one face) of the mesh.
    # In the column scene, true boundary edges are the ground's border and the rim seams... the rim is
    # welded by position, so only the ground's border and the column's bottom seam remain open.
    unique = list(key.keys())
    open_edges = [e for e, n in undirected.items() if n == 1]
    tjunctions = 0
    for (i, j) in open_edges:
        a, b = unique[i], unique[j]
        d = [b[k] - a[k] for k in range(3)]
        dd = sum(x * x for x in d)
        for p in unique:
            if p == a or p == b:
                continue
            w = [p[k] - a[k] for k in range(3)]
            t = sum(w[k] * d[k] for k in range(3)) / dd
            if 1e-6 < t < 1 - 1e-6:
                dist2 = sum((w[k] - t * d[k]) ** 2 for k in range(3))
                if dist2 < 1e-12 * dd:
                    tjunctions += 1
    if tjunctions:
        fail("%d vertices lie strictly inside open edges (T-junctions)" % tjunctions)
    # Area of the column scene: ground 4 + side 2 pi r h (polygonal) + 2 caps (polygonal).
    segments = 16
    polygon = 0.5 * segments * COLUMN_RADIUS ** 2 * math.sin(2 * math.pi / segments)
    side = segments * 2 * COLUMN_RADIUS * math.sin(math.pi / segments) * COLUMN_HEIGHT
    expected = (2 * GROUND_HALF) ** 2 + side + 2 * polygon
    if abs(area - expected) > 1e-4 * expected:
        fail("total area %.6f, the column scene has %.6f: the surface moved" % (area, expected))
    print("conforming: %d faces, %d open edges without T-junctions, area %.6f kept" % (len(faces), len(open_edges), area))


def check_refined_near_column(path):
    ply = read_ply(path)
    pts = positions(ply)
    faces = ply.data['face']['vertex_indices']
    near, far = [], []
    for f in faces:
        a, b, c = (pts[i] for i in f)
        if max(abs(a[2]), abs(b[2]), abs(c[2])) > 1e-6:
            continue
        cx, cy = (a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3
        area = 0.5 * abs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
        r = math.hypot(cx, cy)
        (near if r < 0.45 else far if r > 0.8 else []).append(area)
    if not near or not far:
        fail("no ground faces near or far from the column")
    mean_near, mean_far = sum(near) / len(near), sum(far) / len(far)
    if not mean_near < 0.5 * mean_far:
        fail("ground faces near the column (mean area %.5f) are not smaller than far ones (%.5f)" % (mean_near, mean_far))
    print("refinement: near-column ground faces %.5f mean area vs %.5f far (%d / %d faces)"
          % (mean_near, mean_far, len(near), len(far)))


def check_shadowed(path, light):
    ply = read_ply(path)
    pts = positions(ply)
    v = ply.data['vertex']
    if 'red' not in v:
        fail("no vertex colours")
    norm = math.sqrt(sum(x * x for x in light))
    d = [x / norm for x in light]
    shadow, lit = [], []
    for i, p in enumerate(pts):
        if abs(p[2]) > 1e-6 or math.hypot(p[0], p[1]) < COLUMN_RADIUS + 1e-3 or max(abs(p[0]), abs(p[1])) > 0.95:
            continue
        value = v['red'][i] + v['green'][i] + v['blue'][i]
        (shadow if ray_hits_column((p[0], p[1], 1e-6), d) else lit).append(value)
    if len(shadow) < 3 or len(lit) < 3:
        fail("too few ground vertices in shadow (%d) or lit (%d)" % (len(shadow), len(lit)))
    ms, ml = sum(shadow) / len(shadow), sum(lit) / len(lit)
    if not ms < 0.8 * ml:
        fail("shadowed ground vertices (mean colour sum %.1f) are not darker than lit ones (%.1f)" % (ms, ml))
    print("relighting: %d ground vertices in the column's shadow, mean colour %.1f vs %.1f lit" % (len(shadow), ms, ml))


def check_face_quality(path):
    ply = read_ply(path)
    f = ply.data['face']
    if 'quality' not in f:
        fail("no face quality")
    q = f['quality']
    if not all(math.isfinite(x) and x >= 0 for x in q):
        fail("face quality negative or not finite")
    if max(q) <= min(q):
        fail("face quality constant")
    print("face quality: %d faces, %.4g..%.4g" % (len(q), min(q), max(q)))


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    cmd, path = sys.argv[1], sys.argv[2]
    if cmd == 'column-transfer':
        check_column_transfer(path)
    elif cmd == 'conforming':
        check_conforming(path, int(sys.argv[3]), int(sys.argv[4]))
    elif cmd == 'refined-near-column':
        check_refined_near_column(path)
    elif cmd == 'shadowed':
        check_shadowed(path, [float(x) for x in sys.argv[3:6]])
    elif cmd == 'face-quality':
        check_face_quality(path)
    else:
        print(__doc__)
        return 2
    return 0


if __name__ == '__main__':
    sys.exit(main())
