#!/usr/bin/env bash
# "Out-of-Core Simplification and Normal Map" through the real meshlabserver 2020.09: a sphere scan
# (make_scene, 20,480 triangles, radius 1) named by path is simplified into a NEW layer, saved with
# the project (-w) as an OBJ with its wedge texture coordinates and its texture; the map and its
# description are written beside it. Checked: the new layer's size and that its vertices lie on the
# sphere; the current layer saved unchanged. The same in an empty document (no input mesh). Then the refusals: a truncated PLY and a PLY whose face
# uses a vertex that does not exist (no file written, the layer unchanged).
source "$(dirname "$0")/lib.sh"
FILTER="Out-of-Core Simplification and Normal Map"

ooc_mlx() {  # FILE PLY OUTPUT_BASE
    filter_script "$1" "$FILTER" \
        "plyFile=$2" \
        targetFaces=400 \
        textureSize=256 \
        gutter=4 \
        bits=0 \
        "outputFile=$3"
}

"$MAKE_SCENE" sphere --level 5 -o "$WORK/scan.ply" >/dev/null
"$MAKE_SCENE" sphere --level 1 -o "$WORK/current.ply" >/dev/null
mkdir -p "$WORK/out"
ooc_mlx "$WORK/ooc.mlx" "$WORK/scan.ply" "$WORK/out/scan"
run_meshlabserver "$WORK/ooc.log" -i "$WORK/current.ply" -s "$WORK/ooc.mlx" -w "$WORK/out/ooc.mlp" \
    || { cat "$WORK/ooc.log" >&2; fail "the filter failed"; }
grep -qE "Out-of-Core Simplification: 'scan.ply' \(10242 vertices, 20480 triangles, normals from the file\) -> layer 'scan_ooc': [0-9]+ triangles" \
    "$WORK/ooc.log" || { cat "$WORK/ooc.log" >&2; fail "no log line"; }
[ -s "$WORK/out/scan_normal.png" ] && [ -s "$WORK/out/scan_bake.txt" ] || fail "normal map or description missing"
grep -q "^space = object" "$WORK/out/scan_bake.txt" || fail "the description does not say object space"
saved=$(ls "$WORK/out"/scan_ooc*.ply 2>/dev/null | head -n 1)
[ -n "$saved" ] || { ls "$WORK/out" >&2; fail "the new layer was not saved with the project"; }
python3 - "$saved" <<'PY' || fail "the new layer is wrong"
import sys
sys.path.insert(0, __import__("os").environ["RADIANCE_SOURCE_DIR"] + "/tests/integration")
import ply_reader
ply = ply_reader.read_ply(sys.argv[1])
v = ply.data["vertex"]
n = len(ply.data["face"]["vertex_indices"])
assert 250 <= n <= 550, n
for x, y, z in zip(v["x"], v["y"], v["z"]):
    r = (x * x + y * y + z * z) ** 0.5
    assert abs(r - 1.0) < 0.05, r
print("new layer: %d faces, vertices on the sphere" % n)
PY

# An empty document (no -i): the filter needs no open layer; the new layer is the one saved by -o.
ooc_mlx "$WORK/empty.mlx" "$WORK/scan.ply" "$WORK/empty_scan"
run_meshlabserver "$WORK/empty.log" -s "$WORK/empty.mlx" -o "$WORK/empty_result.ply" \
    || { cat "$WORK/empty.log" >&2; fail "the filter failed in an empty document"; }
[ -s "$WORK/empty_scan_normal.png" ] || { cat "$WORK/empty.log" >&2; fail "no map from the empty document"; }
python3 - "$WORK/empty_result.ply" <<'PY' || fail "the layer made in an empty document is wrong"
import sys
sys.path.insert(0, __import__("os").environ["RADIANCE_SOURCE_DIR"] + "/tests/integration")
import ply_reader
ply = ply_reader.read_ply(sys.argv[1])
n = len(ply.data["face"]["vertex_indices"])
assert 250 <= n <= 550, n
print("empty document: new layer of %d faces saved" % n)
PY

# Refusals: the current layer is saved unchanged and no map is written.
head -c 200000 "$WORK/scan.ply" >"$WORK/truncated.ply"
ooc_mlx "$WORK/truncated.mlx" "$WORK/truncated.ply" "$WORK/refused"
expect_refusal truncated "The PLY file cannot be read" "$WORK/current.ply" "$WORK/truncated.mlx"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n' >"$WORK/bad_index.ply"
ooc_mlx "$WORK/bad_index.mlx" "$WORK/bad_index.ply" "$WORK/refused"
expect_refusal bad_index "face 0 uses vertex 9, out of range" "$WORK/current.ply" "$WORK/bad_index.mlx"
[ ! -e "$WORK/refused_normal.png" ] || fail "a refused run wrote a map"

# Issue 28. The scan with one unreferenced vertex 1e6 away (it turned a 400-triangle target into
# 36 triangles), and at 1e-12 (the map drifted without a word): the first gives the same layer as
# the scan, the second is refused with the fix; a folder given as the PLY is named as a folder.
python3 - "$WORK/scan.ply" "$WORK/stray.ply" "$WORK/tiny.ply" <<'PY' || fail "cannot write the modified scans"
import struct, sys
sys.path.insert(0, __import__("os").environ["RADIANCE_SOURCE_DIR"] + "/tests/integration")
import ply_reader
ply = ply_reader.read_ply(sys.argv[1])
v, faces = ply.data["vertex"], ply.data["face"]["vertex_indices"]
def write(path, points, scale):
    with open(path, "wb") as out:
        out.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                   "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                   % (len(points), len(faces))).encode())
        for p in points:
            out.write(struct.pack("<3f", *(c * scale for c in p)))
        for f in faces:
            out.write(struct.pack("<B3i", 3, *f))
points = list(zip(v["x"], v["y"], v["z"]))
write(sys.argv[2], points + [(1e6, 0.0, 0.0)], 1.0)
write(sys.argv[3], points, 1e-12)
PY
ooc_mlx "$WORK/stray.mlx" "$WORK/stray.ply" "$WORK/out/stray"
run_meshlabserver "$WORK/stray.log" -i "$WORK/current.ply" -s "$WORK/stray.mlx" -w "$WORK/out/stray.mlp" \
    || { cat "$WORK/stray.log" >&2; fail "the filter failed on the scan with a stray vertex"; }
faces=$(grep -oE "layer 'stray_ooc': [0-9]+ triangles" "$WORK/stray.log" | head -n 1 | grep -oE "[0-9]+ triangles" | cut -d' ' -f1)
[ -n "$faces" ] && [ "$faces" -ge 250 ] && [ "$faces" -le 550 ] \
    || { cat "$WORK/stray.log" >&2; fail "a stray unreferenced vertex changed the result: ${faces:-no} triangles"; }
ooc_mlx "$WORK/tiny.mlx" "$WORK/tiny.ply" "$WORK/refused"
expect_refusal tiny_scan "units across, below the 1e-06" "$WORK/current.ply" "$WORK/tiny.mlx"
mkdir -p "$WORK/folder.ply"
ooc_mlx "$WORK/folder.mlx" "$WORK/folder.ply" "$WORK/refused"
expect_refusal folder_as_ply "is a folder, not a PLY file" "$WORK/current.ply" "$WORK/folder.mlx"
[ ! -e "$WORK/refused_normal.png" ] || fail "a refused run wrote a map"
note "ok"
