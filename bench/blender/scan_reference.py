# Run inside Blender: blender -b OUT_DIR/pairs.blend -P scan_reference.py -- SHAPE SIZE STRIDE DISTANCE OUT.npz
# The reference normals of a real scan (bench/bake_vs_blender.sh), where there is no analytic
# surface: for every texel of a SIZE^2 map whose row and column are multiples of STRIDE and whose
# centre lies in a UV triangle of <SHAPE>_low (bench/blender/evaluate_bake.py chart_texels, from
# <SHAPE>_low.corners beside OUT.npz), the ray from the texel's point along +/- its interpolated unit
# normal, up to DISTANCE each way, is cast against <SHAPE>_high with Blender's mathutils BVH tree (a
# code path of neither baker: not Embree, not Cycles); at the nearer hit the high mesh's vertex
# normals are interpolated with the hit's barycentric coordinates and normalised. Texels whose rays
# meet nothing are left out. Writes rows, cols, normals (unit, object space) and size.
import os
import sys

import bpy
import numpy as np
from mathutils import Vector
from mathutils.bvhtree import BVHTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluate_bake import chart_texels  # noqa: E402

shape, size, stride, distance, out = sys.argv[sys.argv.index("--") + 1:]
size, stride, distance = int(size), int(stride), float(distance)
mesh = bpy.data.objects[shape + "_high"].data
verts = np.array([v.co for v in mesh.vertices], dtype=np.float64)
vnormals = np.array([v.normal for v in mesh.vertices], dtype=np.float64)
tris = np.array([p.vertices[:] for p in mesh.polygons], dtype=np.int64)
assert tris.shape[1] == 3, "triangulated high mesh expected"
tree = BVHTree.FromPolygons([tuple(v) for v in verts], [tuple(t) for t in tris])

texels = chart_texels(os.path.join(os.path.dirname(out), shape + "_low.corners"), size, stride)
p = texels["p"]
n = texels["n"] / np.linalg.norm(texels["n"], axis=1, keepdims=True)
face = np.full(len(p), -1, dtype=np.int64)
hit = np.zeros((len(p), 3))
for i in range(len(p)):
    origin, direction = Vector(p[i]), Vector(n[i])
    best = None
    for d in (direction, -direction):
        location, _, index, t = tree.ray_cast(origin, d, distance)
        if index is not None and (best is None or t < best[2]):
            best = (location, index, t)
    if best is not None:
        hit[i] = best[0]
        face[i] = best[1]
found = face >= 0
a, b, c = (verts[tris[face[found], k]] for k in range(3))
q = hit[found]
# Barycentric coordinates of the hit in its triangle (least squares in the triangle's plane).
e1, e2, eq = b - a, c - a, q - a
d11, d12, d22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
q1, q2 = (eq * e1).sum(1), (eq * e2).sum(1)
den = d11 * d22 - d12 * d12
w1 = (d22 * q1 - d12 * q2) / den
w2 = (d11 * q2 - d12 * q1) / den
w0 = 1 - w1 - w2
normals = (w0[:, None] * vnormals[tris[face[found], 0]] + w1[:, None] * vnormals[tris[face[found], 1]] +
           w2[:, None] * vnormals[tris[face[found], 2]])
normals /= np.linalg.norm(normals, axis=1, keepdims=True)
np.savez(out, rows=texels["rows"][found], cols=texels["cols"][found], normals=normals, size=size)
print("REFERENCE %s %d texels (stride %d), %d without a hit" % (shape, found.sum(), stride, (~found).sum()))
