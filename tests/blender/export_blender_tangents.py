# Run inside Blender (blender -b --factory-startup -P export_blender_tangents.py -- OUT_DIR):
# builds the test meshes, triangulates them, lets Blender compute its MikkTSpace tangents
# (Mesh.calc_tangents) and writes, per mesh, the inputs and Blender's answer as plain text:
#   OUT_DIR/<name>.mesh      "vertices N", N lines "x y z", "faces F", F lines "a b c",
#                            "corners 3F", 3F lines "nx ny nz u v" (the loop normals and UVs
#                            Blender gave MikkTSpace), in loop order
#   OUT_DIR/<name>.blender   3F lines "tx ty tz sign" (loop tangent, bitangent_sign)
# Floats are printed with repr() of Blender's float32 values, so they round-trip exactly.
import math
import os
import sys

import bmesh
import bpy

out_dir = sys.argv[sys.argv.index("--") + 1]
os.makedirs(out_dir, exist_ok=True)


def clear_scene():
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()


def triangulate(obj):
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    # Fixed diagonals (not the "beauty" choice) so that the triangulation is plain.
    bmesh.ops.triangulate(bm, faces=bm.faces[:], quad_method="FIXED", ngon_method="EAR_CLIP")
    bm.to_mesh(obj.data)
    bm.free()


def export(obj, name):
    mesh = obj.data
    triangulate(obj)
    mesh.calc_tangents()  # also computes the split (loop) normals MikkTSpace was given
    uv = mesh.uv_layers.active.data
    with open(os.path.join(out_dir, name + ".mesh"), "w") as f:
        f.write("vertices %d\n" % len(mesh.vertices))
        for v in mesh.vertices:
            f.write("%r %r %r\n" % tuple(v.co))
        f.write("faces %d\n" % len(mesh.polygons))
        for p in mesh.polygons:
            assert p.loop_total == 3
            f.write("%d %d %d\n" % tuple(mesh.loops[p.loop_start + k].vertex_index for k in range(3)))
        f.write("corners %d\n" % (3 * len(mesh.polygons)))
        for p in mesh.polygons:
            for k in range(3):
                loop = mesh.loops[p.loop_start + k]
                f.write("%r %r %r %r %r\n" % (tuple(loop.normal) + tuple(uv[p.loop_start + k].uv)))
    with open(os.path.join(out_dir, name + ".blender"), "w") as f:
        for p in mesh.polygons:
            for k in range(3):
                loop = mesh.loops[p.loop_start + k]
                f.write("%r %r %r %r\n" % (tuple(loop.tangent) + (loop.bitangent_sign,)))
    print("exported %s: %d vertices, %d triangles" % (name, len(mesh.vertices), len(mesh.polygons)))


def smooth(obj):
    for p in obj.data.polygons:
        p.use_smooth = True


clear_scene()

# 1. UV sphere, smooth: a seam at u = 0/1 and fans of distinct UVs at the poles.
bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=1.0, calc_uvs=True)
sphere = bpy.context.active_object
smooth(sphere)
export(sphere, "uv_sphere")

# 2. Torus, smooth: seams along both of its circles.
bpy.ops.mesh.primitive_torus_add(major_segments=32, minor_segments=12, major_radius=1.0, minor_radius=0.35,
                                 generate_uvs=True)
torus = bpy.context.active_object
smooth(torus)
export(torus, "torus")

# 3. Mirrored UVs: a bumpy grid whose left half has u mirrored about x = 0, the mirror line's
# vertices shared with equal UVs (as a symmetric unwrap has them), smooth normals.
bpy.ops.mesh.primitive_grid_add(x_subdivisions=16, y_subdivisions=12, size=2.0, calc_uvs=True)
grid = bpy.context.active_object
mesh = grid.data
for v in mesh.vertices:
    v.co.z = 0.15 * math.sin(2.5 * v.co.x) * math.cos(3.0 * v.co.y)
uv = mesh.uv_layers.active.data
for p in mesh.polygons:
    for li in range(p.loop_start, p.loop_start + p.loop_total):
        co = mesh.vertices[mesh.loops[li].vertex_index].co
        uv[li].uv = (abs(co.x) * 0.5, co.y * 0.5 + 0.5)
smooth(grid)
export(grid, "mirrored_grid")

# 4. Cube, flat shaded: per-face normals, the default unwrap (a cross of six squares).
bpy.ops.mesh.primitive_cube_add(size=2.0, calc_uvs=True)
cube = bpy.context.active_object
export(cube, "flat_cube")

# 5. Degenerate UV triangles: an icosphere (smooth) unwrapped by a spherical projection, with
# every fifth triangle's UVs collapsed onto one point (no UV derivative: such a triangle joins
# its neighbours' frame) and a few with collinear UVs.
bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=1.0)
ico = bpy.context.active_object
triangulate(ico)
mesh = ico.data
if not mesh.uv_layers:
    mesh.uv_layers.new(name="UVMap")
uv = mesh.uv_layers.active.data
for p in mesh.polygons:
    for li in range(p.loop_start, p.loop_start + p.loop_total):
        co = mesh.vertices[mesh.loops[li].vertex_index].co
        uv[li].uv = (0.5 + math.atan2(co.y, co.x) / (2 * math.pi), 0.5 + math.asin(max(-1.0, min(1.0, co.z))) / math.pi)
    if p.index % 5 == 0:
        for li in range(p.loop_start, p.loop_start + p.loop_total):
            uv[li].uv = uv[p.loop_start].uv[:]
    elif p.index % 17 == 1:  # collinear: the third corner halfway between the first two
        a, b = uv[p.loop_start].uv[:], uv[p.loop_start + 1].uv[:]
        uv[p.loop_start + 2].uv = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
smooth(ico)
export(ico, "degenerate_uv_ico")
