#!/usr/bin/env bash
# "Bake Normal Map" through the real meshlabserver: a fine icosphere (the "scan", 81,920 faces)
# baked onto a coarse one (320 faces) without texture coordinates, so the per-triangle atlas is
# made. Checks: the file set and its description, the layer saved with wedge coordinates and the
# map as its texture, the object-space map against the exact sphere normals (mean <= 0.5 degrees
# at 16 bit), no texel left empty anywhere; then a tangent-space 8-bit bake onto the saved mesh's
# own (now existing) coordinates. (Debian's meshlabserver 2020.09 aborts on loading any OBJ: the
# layer is saved both as OBJ, read by the checker, and as PLY with wedge coordinates, reloaded.)
source "$(dirname "$0")/lib.sh"
source "$(dirname "$0")/bake_mlx.sh"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_baked_maps.py"

"$MAKE_SCENE" sphere --level 6 -o "$WORK/fine.ply"
"$MAKE_SCENE" sphere --level 2 -o "$WORK/coarse.ply"
# The scan with vertex colours (its radiance functions' mean colour), for the diffuse map.
"$RADIANCE_BUILD_DIR/tools/make_radiance_mesh" "$WORK/fine.ply" --basis PB2 --no-shadows -o "$WORK/fine.rply" \
    >/dev/null 2>&1 || fail "make_radiance_mesh failed"

# Layer 0 = the scan, layer 1 (the last loaded, current) = the coarse target.
bake_mlx "$WORK/object16.mlx" 0 256 0 0
run_meshlabserver "$WORK/object16.log" -i "$WORK/fine.rply" -i "$WORK/coarse.ply" -s "$WORK/object16.mlx" \
    -o "$WORK/coarse_baked.obj" -m wt vn -o "$WORK/coarse_baked.ply" -m wt vn || { cat "$WORK/object16.log" >&2; fail "object-space bake failed"; }
grep -qF "per-triangle atlas" "$WORK/object16.log" || { cat "$WORK/object16.log" >&2; fail "no atlas in the log"; }
for f in coarse_normal.png coarse_diffuse.png coarse_lean.exr coarse_bake.txt; do
    [ -s "$WORK/$f" ] || fail "missing $f beside the target mesh"
done
ls "$WORK"/*.part* >/dev/null 2>&1 && fail "temporary files left behind"
grep -qx "space = object" "$WORK/coarse_bake.txt" || fail "description does not say object space"
grep -qx "bits = 16" "$WORK/coarse_bake.txt" || fail "description does not say 16 bit"
grep -qx "diffuse_map = coarse_diffuse.png" "$WORK/coarse_bake.txt" || fail "description does not list the diffuse map"
grep -qx "lean_moments = coarse_lean.exr" "$WORK/coarse_bake.txt" || fail "description does not list the LEAN file"
grep -q "^vt " "$WORK/coarse_baked.obj" || fail "the saved layer has no texture coordinates"
grep -q "coarse_normal.png" "$WORK/coarse_baked.obj.mtl" || fail "the map is not the layer's texture"
$CHECK sphere "$WORK/coarse_baked.obj" "$WORK/coarse_normal.png" 0.5 || fail "object-space map too far from the sphere"
$CHECK complete "$WORK/coarse_normal.png" || fail "empty texels in the object-space map"
note "object space, 16 bit: $($CHECK sphere "$WORK/coarse_baked.obj" "$WORK/coarse_normal.png" 0.5)"

# Tangent space, 8 bit, onto the coordinates the first bake gave the layer (no new atlas), with
# an explicit output file; no LEAN file for tangent space.
bake_mlx "$WORK/tangent8.mlx" 0 256 1 1 false "$WORK/tangent/sphere_normal.png"
mkdir -p "$WORK/tangent"
run_meshlabserver "$WORK/tangent8.log" -i "$WORK/fine.ply" -i "$WORK/coarse_baked.ply" -s "$WORK/tangent8.mlx" \
    -o "$WORK/tangent/coarse_tangent.ply" -m wt vn || { cat "$WORK/tangent8.log" >&2; fail "tangent-space bake failed"; }
grep -qF "the target's wedge texture coordinates" "$WORK/tangent8.log" || { cat "$WORK/tangent8.log" >&2; fail "existing UVs not used"; }
grep -qx "space = tangent" "$WORK/tangent/sphere_bake.txt" || fail "description does not say tangent space"
grep -qx "tangent_frame = mikktspace" "$WORK/tangent/sphere_bake.txt" || fail "description does not say MikkTSpace (the default frame)"
grep -q "^green_channel = +Y up" "$WORK/tangent/sphere_bake.txt" || fail "description does not state the +Y up convention"
grep -qF "MikkTSpace, Mikkelsen 2008" "$WORK/tangent8.log" || fail "the log does not name the tangent frame"
[ -e "$WORK/tangent/sphere_lean.exr" ] && fail "a LEAN file for a tangent-space map"
grep -qF "LEAN maps filter object-space normals" "$WORK/tangent8.log" || fail "no note about LEAN in tangent space"
$CHECK complete "$WORK/tangent/sphere_normal.png" || fail "empty texels in the tangent-space map"
note "tangent space, 8 bit ok"

# Per-vertex texture coordinates (texture_u / texture_v, as photogrammetry tools write them) are the
# layout baked into, not replaced by a per-triangle atlas: a bumpy scan grid, a flat 5 x 5 target
# grid with per-vertex UVs; the saved layer's wedge coordinates must equal its per-vertex ones.
python3 - "$WORK/uv_scan.ply" "$WORK/uv_target.ply" <<'PY'
import math, sys
def grid(path, n, z, uv):
    verts = [(i / n - 0.5, j / n - 0.5) for j in range(n + 1) for i in range(n + 1)]
    faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            faces += [(a, a + 1, a + n + 2), (a, a + n + 2, a + n + 1)]
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n" % len(verts))
        f.write("property float nx\nproperty float ny\nproperty float nz\n")
        if uv:
            f.write("property float texture_u\nproperty float texture_v\n")
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for x, y in verts:
            f.write("%r %r %r 0 0 1" % (x, y, z(x, y)) + (" %r %r" % (0.05 + 0.9 * (x + 0.5), 0.05 + 0.9 * (y + 0.5)) if uv else "") + "\n")
        for t in faces:
            f.write("3 %d %d %d\n" % t)
grid(sys.argv[1], 80, lambda x, y: 0.02 * math.sin(9 * x) * math.cos(7 * y), False)
grid(sys.argv[2], 4, lambda x, y: 0.0, True)
PY
mkdir -p "$WORK/uv"
bake_mlx "$WORK/uv.mlx" 0 128 1 0 false "$WORK/uv/grid_normal.png"
run_meshlabserver "$WORK/uv.log" -i "$WORK/uv_scan.ply" -i "$WORK/uv_target.ply" -s "$WORK/uv.mlx" \
    -o "$WORK/uv/target_baked.ply" -m wt || { cat "$WORK/uv.log" >&2; fail "bake onto per-vertex UVs failed"; }
grep -qF "the target's per-vertex texture coordinates" "$WORK/uv.log" || { cat "$WORK/uv.log" >&2; fail "the per-vertex UVs were not used"; }
grep -qx "uv = target's wedge coordinates" "$WORK/uv/grid_bake.txt" || fail "the description does not name the target's layout"
python3 - "$WORK/uv/target_baked.ply" "$RADIANCE_SOURCE_DIR/tests/integration" <<'PY' || fail "the per-vertex layout was not kept"
import sys
sys.path.insert(0, sys.argv[2])
from ply_reader import read_ply
ply = read_ply(sys.argv[1])
x, y = ply.data["vertex"]["x"], ply.data["vertex"]["y"]
faces, texcoords = ply.data["face"]["vertex_indices"], ply.data["face"]["texcoord"]
assert len(faces) == 32, len(faces)
worst = 0.0
for face, tc in zip(faces, texcoords):
    for k, v in enumerate(face):
        worst = max(worst, abs(tc[2 * k] - (0.05 + 0.9 * (x[v] + 0.5))), abs(tc[2 * k + 1] - (0.05 + 0.9 * (y[v] + 0.5))))
assert worst < 1e-5, worst
print("per-vertex layout kept: largest wedge difference %.2g" % worst)
PY
note "per-vertex texture coordinates kept"

# glTF 2.0 export from meshlabserver (MeshLab 2020.09): object space with LEAN, so the .glb holds a
# MikkTSpace normal texture, the diffuse map and a roughness texture. The container and its JSON
# are checked with Python's standard library (pygltflib and Blender check it in the pytest suite).
mkdir -p "$WORK/gltf"
bake_mlx "$WORK/gltf.mlx" 0 128 0 0 false "$WORK/gltf/scan_normal.png" 0 true
run_meshlabserver "$WORK/gltf.log" -i "$WORK/fine.rply" -i "$WORK/coarse_baked.ply" -s "$WORK/gltf.mlx" \
    || { cat "$WORK/gltf.log" >&2; fail "bake with glTF failed"; }
[ -s "$WORK/gltf/scan.glb" ] || fail "no scan.glb written"
grep -qF "wrote $WORK/gltf/scan.glb (glTF 2.0" "$WORK/gltf.log" || { cat "$WORK/gltf.log" >&2; fail "the log does not name the glb"; }
python3 - "$WORK/gltf/scan.glb" <<'PY' || fail "the .glb is not a valid glTF 2.0 binary"
import json, struct, sys
data = open(sys.argv[1], "rb").read()
magic, version, length = struct.unpack_from("<III", data, 0)
assert magic == 0x46546C67 and version == 2 and length == len(data), (magic, version, length)
json_length, json_type = struct.unpack_from("<II", data, 12)
assert json_type == 0x4E4F534A and json_length % 4 == 0
doc = json.loads(data[20:20 + json_length])
bin_length, bin_type = struct.unpack_from("<II", data, 20 + json_length)
assert bin_type == 0x004E4942 and 28 + json_length + bin_length == len(data)
attributes = doc["meshes"][0]["primitives"][0]["attributes"]
assert set(attributes) == {"POSITION", "NORMAL", "TEXCOORD_0", "TANGENT"}, attributes
tangent = doc["accessors"][attributes["TANGENT"]]
assert tangent["type"] == "VEC4" and tangent["componentType"] == 5126
assert len(doc["images"]) == 3, doc["images"]
material = doc["materials"][0]
assert "normalTexture" in material and "metallicRoughnessTexture" in material["pbrMetallicRoughness"]
view = doc["bufferViews"][tangent["bufferView"]]
w = struct.unpack_from("<%df" % (4 * tangent["count"]), data, 28 + json_length + view["byteOffset"])[3::4]
assert set(w) <= {1.0, -1.0}, set(w)
print("glb: %d vertices, %d images, tangent signs %s" % (tangent["count"], len(doc["images"]), sorted(set(w))))
PY
note "glTF export ok"
