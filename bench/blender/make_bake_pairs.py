# Run inside Blender: blender -b --factory-startup -P make_bake_pairs.py -- OUT_DIR
# The high / low pairs of bench/bake_vs_blender.sh, made once so that both bakers get the very same
# meshes and UVs:
#   OUT_DIR/pairs.blend          objects <shape>_high, <shape>_low (smooth shaded, UVs on the low)
#   OUT_DIR/<shape>_high.ply     the high mesh with Blender's vertex normals (for MeshLab)
#   OUT_DIR/<shape>_low.ply      the low mesh, triangulated, vertices split where a vertex has several
#                                UVs, per-vertex texture_u / texture_v and Blender's vertex normals
#   OUT_DIR/<shape>_low.corners  per face corner of the low mesh: "x y z nx ny nz u v tx ty tz sign"
#                                (Blender's MikkTSpace tangents, equal to ours: tests/blender/)
# Shapes: a unit sphere (icosphere of 327,680 faces onto a 32 x 16 UV sphere) and a torus R = 1,
# r = 0.35 (a 1024 x 512 parametric grid, 1,048,576 faces, onto Blender's 48 x 24 torus). The high
# meshes' normals are Blender's (smooth, from the faces), in both bakers.
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(__file__))
from make_bake_pairs_io import smooth, triangulate, write_high_ply, write_low  # noqa: E402

out = os.path.abspath(sys.argv[sys.argv.index("--") + 1])
os.makedirs(out, exist_ok=True)
bpy.ops.wm.read_factory_settings(use_empty=True)


bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=8, radius=1.0)
high = bpy.context.active_object
high.name = "sphere_high"
bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1.0, calc_uvs=True)
low = bpy.context.active_object
low.name = "sphere_low"

# Blender's torus primitive stops at 256 x 256: the fine torus is built from its parametrisation.
nu, nv = 1024, 512
verts = []
for i in range(nu):
    a = 2 * math.pi * i / nu
    for j in range(nv):
        b = 2 * math.pi * j / nv
        verts.append(((1.0 + 0.35 * math.cos(b)) * math.cos(a), (1.0 + 0.35 * math.cos(b)) * math.sin(a), 0.35 * math.sin(b)))
quads = [(i * nv + j, ((i + 1) % nu) * nv + j, ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv)
         for i in range(nu) for j in range(nv)]
torus_mesh = bpy.data.meshes.new("torus_high")
torus_mesh.from_pydata(verts, [], quads)
torus_mesh.update()
high_t = bpy.data.objects.new("torus_high", torus_mesh)
bpy.context.scene.collection.objects.link(high_t)
bpy.ops.mesh.primitive_torus_add(major_segments=48, minor_segments=24, major_radius=1.0, minor_radius=0.35,
                                 generate_uvs=True)
low_t = bpy.context.active_object
low_t.name = "torus_low"

for obj in (high, low, high_t, low_t):
    triangulate(obj)
    smooth(obj)
    obj.data.update()
for shape in ("sphere", "torus"):
    write_high_ply(bpy.data.objects[shape + "_high"], os.path.join(out, shape + "_high.ply"))
    write_low(bpy.data.objects[shape + "_low"], os.path.join(out, shape + "_low.ply"),
              os.path.join(out, shape + "_low.corners"))
    print("pair %s: %d -> %d faces" % (shape, len(bpy.data.objects[shape + "_high"].data.polygons),
                                       len(bpy.data.objects[shape + "_low"].data.polygons)))
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "pairs.blend"))
