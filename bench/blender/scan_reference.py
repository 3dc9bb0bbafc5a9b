# Run inside Blender: blender -b OUT_DIR/pairs.blend -P scan_reference.py -- SHAPE SIZE STRIDE DISTANCE OUT.npz
# The reference normals of a real scan (bench/bake_vs_blender.sh), where there is no analytic
# surface: for every texel of a SIZE^2 map whose row and column are multiples of STRIDE and whose
# centre lies in a UV triangle of <SHAPE>_low (bench/blender/evaluate_bake.py chart_texels, from
# <SHAPE>_low.corners beside OUT.npz), the ray from the texel's point along +/- its interpolated unit
# normal, up to DISTANCE each way, is cast against <SHAPE>_high with Blender's mathutils BVH tree (a
# code path of neither baker: not Embree, not Cycles); at the nearer hit the high mesh's vertex
# normals are interpolated with the hit's barycentric coordinates and normalised ("normals": the
# nearest-hit rule, which ours follows). Cycles' cage rule differs where the scan folds: its ray
# starts on the cage, D out along the normal, and takes the FIRST hit going in over 2 D
# ("normals_cage", the same interpolation at that hit). Texels whose rays meet nothing are left
# out. Writes rows, cols, normals, normals_cage (unit, object space) and size.
import os
import sys

import bmesh
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
bm = bmesh.new()
bm.from_mesh(mesh)  # faces keep the polygons' order: a hit's index is the polygon's
tree = BVHTree.FromBMesh(bm)

texels = chart_texels(os.path.join(os.path.dirname(out), shape + "_low.corners"), size, stride)
p = texels["p"]
n = texels["n"] / np.linalg.norm(texels["n"], axis=1, keepdims=True)
face = np.full(len(p), -1, dtype=np.int64)
hit = np.zeros((len(p), 3))
cage_face = np.full(len(p), -1, dtype=np.int64)
cage_hit = np.zeros((len(p), 3))
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
    # The cage rule: the first hit from p + D n back along -n over 2 D.
    location, _, index, t = tree.ray_cast(origin + distance * direction, -direction, 2 * distance)
    if index is not None:
        cage_hit[i] = location
        cage_face[i] = index
found = (face >= 0) & (cage_face >= 0)


def interpolated_normals(face, q):
    a, b, c = (verts[tris[face, k]] for k in range(3))
    # Barycentric coordinates of the hit in its triangle (least squares in the triangle's plane).
    e1, e2, eq = b - a, c - a, q - a
    d11, d12, d22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    q1, q2 = (eq * e1).sum(1), (eq * e2).sum(1)
    den = d11 * d22 - d12 * d12
    w1 = (d22 * q1 - d12 * q2) / den
    w2 = (d11 * q2 - d12 * q1) / den
    w0 = 1 - w1 - w2
    normals = (w0[:, None] * vnormals[tris[face, 0]] + w1[:, None] * vnormals[tris[face, 1]] +
               w2[:, None] * vnormals[tris[face, 2]])
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


np.savez(out, rows=texels["rows"][found], cols=texels["cols"][found], size=size,
         normals=interpolated_normals(face[found], hit[found]),
         normals_cage=interpolated_normals(cage_face[found], cage_hit[found]))
differ = (face[found] != cage_face[found]).sum()
print("REFERENCE %s %d texels (stride %d), %d without a hit, %d where the nearest and the cage rule's hits differ"
      % (shape, found.sum(), stride, (~found).sum(), differ))
