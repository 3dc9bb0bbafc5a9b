# Run inside Blender: blender -b OUT_DIR/pairs.blend -P make_scan_pair.py -- OUT_DIR SCAN.off
# Adds the real-scan pair of bench/bake_vs_blender.sh to pairs.blend (objects scan_high, scan_low)
# and writes, as make_bake_pairs.py does for the analytic shapes:
#   OUT_DIR/scan_high.ply       the scan, two Catmull-Clark subdivision levels (Blender's Subdivision
#                               Surface modifier, applied and triangulated), Blender's vertex normals
#   OUT_DIR/scan_low.ply        the scan decimated (Blender's Decimate, collapse) to ~3,000 faces,
#                               UVs by Blender's Smart UV Project (margin 0.002: 4 texels at 2048^2; the largest angle
#                               limit that leaves no overlap), triangulated, per-vertex UVs
#   OUT_DIR/scan_low.corners    per face corner: "x y z nx ny nz u v tx ty tz sign"
#   OUT_DIR/scan_distance.txt   the ray distance D both bakers get: twice the largest distance from
#                               the low mesh's vertices and face centres to the high mesh (what our
#                               automatic distance would choose)
# The scan's normals: none given; both bakers use Blender's smooth vertex normals of the high mesh.
import math
import os
import sys

import bmesh
import bpy
from mathutils.bvhtree import BVHTree

sys.path.insert(0, os.path.dirname(__file__))
from make_bake_pairs_io import smooth, triangulate, write_high_ply, write_low  # noqa: E402

out, scan_path = sys.argv[sys.argv.index("--") + 1:][:2]
out = os.path.abspath(out)


def read_off(path):
    with open(path) as f:
        words = f.read().split()
    assert words[0] == "OFF", path
    nv, nf = int(words[1]), int(words[2])
    at = 4
    verts = [tuple(float(w) for w in words[at + 3 * i:at + 3 * i + 3]) for i in range(nv)]
    at += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(words[at])
        faces.append(tuple(int(w) for w in words[at + 1:at + 1 + n]))
        at += 1 + n
    return verts, faces


for name in ("scan_high", "scan_low"):
    if name in bpy.data.objects:
        bpy.data.objects.remove(bpy.data.objects[name])
verts, faces = read_off(scan_path)


def new_object(name):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def apply_modifier(obj, modifier):
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.modifier_apply(modifier=modifier.name)


high = new_object("scan_high")
subsurf = high.modifiers.new("subdivide", "SUBSURF")
subsurf.levels = subsurf.render_levels = 2
apply_modifier(high, subsurf)

low = new_object("scan_low")
decimate = low.modifiers.new("decimate", "DECIMATE")
decimate.decimate_type = "COLLAPSE"
decimate.ratio = 3000.0 / len(faces)
decimate.use_collapse_triangulate = True
apply_modifier(low, decimate)
for other in bpy.context.view_layer.objects:
    other.select_set(False)
low.select_set(True)
bpy.context.view_layer.objects.active = low
bpy.ops.object.mode_set(mode="EDIT")
bpy.context.scene.tool_settings.use_uv_select_sync = False
# Smart UV Project's default angle (66 degrees) folds a few triangles of the decimated armadillo
# over others: overlapping UVs, which no baker can honour (ours refuses them). Smaller angles make
# more, flatter charts; the first without overlap (Blender's own Select Overlap) is kept.
for angle in (66, 45, 30, 20, 10):
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(angle_limit=math.radians(angle), island_margin=0.002)
    bpy.ops.uv.select_all(action="DESELECT")
    bpy.ops.uv.select_overlap(extend=False)
    edit = bmesh.from_edit_mesh(low.data)
    uv_layer = edit.loops.layers.uv.active
    overlapping = sum(1 for f in edit.faces if all(loop[uv_layer].select for loop in f.loops))
    if overlapping == 0:
        break
assert overlapping == 0, "Smart UV Project overlaps at every angle tried"
print("smart uv project: angle limit %d degrees" % angle)
bpy.ops.object.mode_set(mode="OBJECT")

for obj in (high, low):
    triangulate(obj)
    smooth(obj)
    obj.data.update()

# Ray distance: twice the largest distance from the low surface's vertices and face centres to the high.
bm = bmesh.new()
bm.from_mesh(high.data)
tree = BVHTree.FromBMesh(bm)
largest = 0.0
for p in [v.co for v in low.data.vertices] + [f.center for f in low.data.polygons]:
    found = tree.find_nearest(p)
    largest = max(largest, found[3])
bm.free()
distance = 2.0 * largest
with open(os.path.join(out, "scan_distance.txt"), "w") as f:
    f.write("%r\n" % distance)
write_high_ply(high, os.path.join(out, "scan_high.ply"))
write_low(low, os.path.join(out, "scan_low.ply"), os.path.join(out, "scan_low.corners"))
print("pair scan: %d -> %d faces, D = %g" % (len(high.data.polygons), len(low.data.polygons), distance))
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "pairs.blend"))
