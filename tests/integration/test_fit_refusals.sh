#!/usr/bin/env bash
# "Fit Radiance Functions from Rasters" on bad input, through the real meshlabserver: a clear
# message in the log, no crash, and where the filter refuses, the layer saved unchanged.
#  - no raster layer at all;
#  - one raster whose image file is missing and one whose camera is invalid: skipped with a warning
#    naming them, the fit goes on with the others;
#  - every raster unusable: refused;
#  - a point cloud without normals: refused, asking for normals;
#  - a NaN vertex position: dropped by MeshLab's importer, or refused by us;
#  - cameras turned away from the mesh (every vertex unseen): refused.
source "$(dirname "$0")/lib.sh"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_radiance_ply.py"

"$MAKE_SCENE" sphere --level 3 -o "$WORK/sphere.ply"
"$VIRTUAL_ACQUISITION" "$WORK/sphere.ply" -o "$WORK/photos" --views 8 --size 160x120 --no-variation \
    >"$WORK/acquisition.log" 2>&1 || { cat "$WORK/acquisition.log" >&2; fail "virtual acquisition failed"; }
fit_mlx "$WORK/fit.mlx"
run_meshlabserver "$WORK/ref.log" -i "$WORK/photos/mesh.ply" -o "$WORK/reference.rply" -m vc vq vn \
    || { cat "$WORK/ref.log" >&2; fail "could not save the reference"; }

# expect_refusal NAME MESSAGE MESH [PROJECT]: the filter fails with MESSAGE and the layer is unchanged.
expect_refusal() {
    local name="$1" message="$2" mesh="$3" project="${4:-}"
    local args=(-i "$mesh")
    [ -n "$project" ] && args+=(-p "$project")
    run_meshlabserver "$WORK/$name.log" "${args[@]}" -s "$WORK/fit.mlx" -o "$WORK/$name.rply" -m vc vq vn \
        -l "$WORK/$name.filterlog" || true
    cat "$WORK/$name.filterlog" >>"$WORK/$name.log" 2>/dev/null || true
    grep -qF "$message" "$WORK/$name.log" || { cat "$WORK/$name.log" >&2; fail "$name: no message '$message'"; }
    if [ -e "$WORK/$name.rply" ] && [ "$mesh" = "$WORK/photos/mesh.ply" ]; then
        $CHECK same "$WORK/reference.rply" "$WORK/$name.rply" || fail "$name: layer changed by a refused filter"
    fi
    note "$name refused: $(grep -F "$message" "$WORK/$name.log" | head -n 1)"
}

expect_refusal no_rasters "The document has no raster layers" "$WORK/photos/mesh.ply"

# damage OUT: a copy of the project with the damage its file name says (Python, on the XML text).
damage() {
    python3 - "$WORK/photos/project.mlp" "$1" <<'PY'
import re, sys
src, out = sys.argv[1], sys.argv[2]
text = open(src).read()
rasters = text.split("<MLRaster ")
head, rest = rasters[0], rasters[1:]
def fix(i, r):
    if "missing_image" in out and i == 0:
        r = r.replace('fileName="images/view_000.png"', 'fileName="images/no_such_file.png"')
    if "bad_camera" in out and i == 1:
        r = re.sub(r'FocalMm="[^"]*"', 'FocalMm="0"', r)
    if "all_bad" in out:
        r = re.sub(r'FocalMm="[^"]*"', 'FocalMm="0"', r)
    if "turned_away" in out:
        def flip(m):
            v = m.group(1).split()
            for k in (4, 5, 6, 8, 9, 10):
                v[k] = repr(-float(v[k]))
            return 'RotationMatrix="' + " ".join(v) + '"'
        r = re.sub(r'RotationMatrix="([^"]*)"', flip, r)
    return r
open(out, "w").write(head + "".join("<MLRaster " + fix(i, r) for i, r in enumerate(rest)))
PY
}
damage "$WORK/photos/missing_image_bad_camera.mlp"
damage "$WORK/photos/all_bad.mlp"
damage "$WORK/photos/turned_away.mlp"

# Two damaged rasters: warnings naming them, the fit goes on with the other 6.
run_meshlabserver "$WORK/partial.log" -i "$WORK/photos/mesh.ply" -p "$WORK/photos/missing_image_bad_camera.mlp" \
    -s "$WORK/fit.mlx" -o "$WORK/partial.rply" -m vc vq vn || { cat "$WORK/partial.log" >&2; fail "partial fit failed"; }
grep -qF "raster 'view_000.png' skipped: its image" "$WORK/partial.log" || { cat "$WORK/partial.log" >&2; fail "no warning for the missing image"; }
grep -qF "raster 'view_001.png' skipped: the camera's focal length" "$WORK/partial.log" || { cat "$WORK/partial.log" >&2; fail "no warning for the invalid camera"; }
grep -qF "from 6 of 8 rasters" "$WORK/partial.log" || { cat "$WORK/partial.log" >&2; fail "the fit did not use the 6 good rasters"; }

expect_refusal all_bad "None of the 8 raster layers is usable" "$WORK/photos/mesh.ply" "$WORK/photos/all_bad.mlp"
expect_refusal turned_away "No vertex is seen by any raster" "$WORK/photos/mesh.ply" "$WORK/photos/turned_away.mlp"

# A point cloud without normals (ASCII PLY, vertices only) and a mesh with a NaN position.
python3 - "$WORK" <<'PY'
import sys
work = sys.argv[1]
with open(f"{work}/cloud.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n")
    f.write("0 0 1\n0.1 0 1\n0 0.1 1\n")
with open(f"{work}/nan.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n")
    f.write("property float nx\nproperty float ny\nproperty float nz\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n")
    f.write("0 0 1 0 0 1\n0.5 0 1 0 0 1\n0 0.5 1 0 0 1\nnan 0.5 1 0 0 1\n3 0 1 2\n3 1 3 2\n")
PY
expect_refusal no_normals "vertices has a usable normal and there are no faces" \
    "$WORK/cloud.ply" "$WORK/photos/project.mlp"
# MeshLab's PLY importer already drops a vertex whose position is NaN (seen: 3 of the 4 vertices
# arrive); the fit must then run on what is left without crashing. (The core's own refusal of NaN
# positions is a unit test: radiance_from_views_test.)
run_meshlabserver "$WORK/nan.log" -i "$WORK/nan.ply" -p "$WORK/photos/project.mlp" -s "$WORK/fit.mlx" \
    -o "$WORK/nan.rply" -m vc vq vn || true
grep -qE "Fitted PB4 radiance functions on 3 vertices from 8 of 8 rasters|not finite" "$WORK/nan.log" \
    || { cat "$WORK/nan.log" >&2; fail "NaN vertex: neither refused nor fitted on the finite vertices"; }
note "ok"
