#!/usr/bin/env bash
# GUI test of the POP-buffer level of detail of the "Baked Normal Map" decoration (Limper et al.
# 2013; texture-coordinate correction of Weber & Stamminger, Alg. 1) in Debian's real meshlab under
# Xvfb. The armadillo is simplified by MeshLab (Quadric Edge Collapse, 1,000 faces) and baked by our
# filter, as in gui_normal_map.sh; meshlab then opens the baked layer with private settings: the
# level 4 forced with and without the correction, and the automatic level at tolerances of 1 and 8
# pixels (four meshlab starts, about a minute). Asserts
#   - the forced level's log line gives the triangle count recomputed here in Python from the saved
#     layer (triangles whose three corners are in three different cells of the 16^3 grid),
#   - level 4 differs from the automatic level at 1 pixel (level 9 here, within 2.6 levels RMSE of
#     the whole mesh when this was written), and the correction changes level 4 again,
#   - the automatic level at 8 pixels is 3 below the one at 1 pixel (2^3 = 8: the level keeps the
#     snapping within the tolerance), at the same view,
#   - no GL error.
source "$(dirname "$0")/../integration/lib.sh"
source "$(dirname "$0")/gui_lib.sh"
scan="${RADIANCE_DATA_CACHE:-$RADIANCE_SOURCE_DIR/data-cache}/meshes/armadillo.off"
[ -s "$scan" ] || fail "no $scan (scripts/setup.sh fetches it)"

{
    echo '<!DOCTYPE FilterScript>'
    echo '<FilterScript>'
    bash "$RADIANCE_SOURCE_DIR/scripts/meshlab_decimation_filter.sh" 1000 true
    bash "$RADIANCE_SOURCE_DIR/scripts/bake_normal_map_filter.sh" 0 512 0 0 true true "$WORK/armadillo_normal.png"
    echo '</FilterScript>'
} >"$WORK/simplify.mlx"
run_meshlabserver "$WORK/prepare.log" -i "$scan" -i "$scan" -s "$WORK/simplify.mlx" -o "$WORK/armadillo_baked.ply" -m wt vn \
    || { cat "$WORK/prepare.log" >&2; fail "simplification + bake failed"; }

# Triangles of level 4 (16 cells per axis over the bounding box), from the saved layer.
expected="$(python3 - "$WORK/armadillo_baked.ply" <<'PY'
import math, struct, sys
sys.path.insert(0, __import__("os").environ["RADIANCE_SOURCE_DIR"] + "/tests/integration")
from ply_reader import read_ply
ply = read_ply(sys.argv[1])
v = list(zip(*(ply.data["vertex"][k] for k in "xyz")))
lo = [min(p[k] for p in v) for k in range(3)]
hi = [max(p[k] for p in v) for k in range(3)]
cell = lambda p: tuple(min(math.floor((p[k] - lo[k]) / (hi[k] - lo[k]) * 16), 15) for k in range(3))
kept = 0
for f in ply.data["face"]["vertex_indices"]:
    a, b, c = (cell(v[i]) for i in f)
    kept += a != b and b != c and a != c
print(kept, len(ply.data["face"]["vertex_indices"]))
PY
)"
read -r kept total <<<"$expected"
note "level 4 keeps $kept of $total triangles (computed here)"

start_xvfb
setting() {  # setting TYPE NAME VALUE [EXTRA]
    printf 'MeshLab%%3A%%3ADecoration%%3A%%3A%s="<!DOCTYPE MeshLabSettings>\\n<Param type=\\"%s\\" value=\\"%s\\" name=\\"MeshLab::Decoration::%s\\"%s/>\\n"\n' \
        "$2" "$1" "$3" "$2" "${4:-}"
}
shot() {  # shot NAME LOD(0|1|2) LEVEL CORRECTION TOLERANCE
    local name="$1"
    mkdir -p "$XDG_CONFIG_HOME/VCG"
    {
        echo '[General]'
        setting RichEnum NormalMapShading 1 ' enum_cardinality=\"3\" enum_val0=\"a\" enum_val1=\"b\" enum_val2=\"c\"'
        setting RichEnum NormalMapLevelOfDetail "$2" ' enum_cardinality=\"3\" enum_val0=\"a\" enum_val1=\"b\" enum_val2=\"c\"'
        setting RichInt NormalMapLevelOfDetailLevel "$3"
        setting RichBool NormalMapLevelOfDetailCorrection "$4"
        setting RichFloat NormalMapLevelOfDetailTolerance "$5"
    } >"$XDG_CONFIG_HOME/VCG/MeshLab_64bit_fp.conf"
    start_meshlab "$name" "$WORK/armadillo_baked.ply"
    # The pictures are compared pixel for pixel: the window must have the same size in every run
    # (start_meshlab's resize is sometimes lost while MeshLab lays its window out).
    local size=""
    for _ in $(seq 1 20); do
        xdotool windowsize "$window" 1200 900 2>/dev/null || true
        sleep 0.5
        size="$(xdotool getwindowgeometry "$window" 2>/dev/null | awk '/Geometry/ { print $2 }')"
        [ "$size" = "1200x900" ] && break
    done
    [ "$size" = "1200x900" ] || fail "$name: the MeshLab window stays $size, not 1200x900"
    sleep 2
    keys shift+h ctrl+h ctrl+alt+n
    sleep 6
    import -window root "$WORK/$name.png"
    stop_meshlab
    if grep -n "GL error" "$WORK/$name.meshlab.log"; then fail "$name: GL error"; fi
    grep -qF "Baked Normal Map: layer" "$WORK/$name.meshlab.log" \
        || { tail -n 30 "$WORK/$name.meshlab.log" >&2; fail "$name: the decoration did not start"; }
}
rmse() {  # over the left part of the 3D view (the armadillo), below the real-time info box at its top
    { compare -metric RMSE "$1"[420x560+10+170] "$2"[420x560+10+170] null: 2>&1 || true; } |
        sed -E 's/.*\(([0-9.e-]+)\).*/\1/' | awk '{ printf "%.2f", $1 * 255 }'
}
logged_level() {  # the last POP level the decoration logged
    grep -oE "Baked Normal Map: POP level [0-9]+" "$WORK/$1.meshlab.log" | tail -n 1 | awk '{ print $NF }'
}

shot forced 2 4 true 1
shot forced_plain 2 4 false 1
shot auto1 1 4 true 1
shot auto8 1 4 true 8

grep -qF "Baked Normal Map: POP level 4 (forced, texture coordinates corrected): $kept of $total triangles" \
    "$WORK/forced.meshlab.log" || { grep "POP level" "$WORK/forced.meshlab.log" >&2; fail "no log line with $kept of $total triangles"; }
grep -qF "Baked Normal Map: POP level 4 (forced): $kept of $total triangles" "$WORK/forced_plain.meshlab.log" \
    || { grep "POP level" "$WORK/forced_plain.meshlab.log" >&2; fail "no log line for the uncorrected level"; }
d_level="$(rmse "$WORK/auto1.png" "$WORK/forced.png")"
d_correction="$(rmse "$WORK/forced.png" "$WORK/forced_plain.png")"
note "RMSE (8-bit levels): automatic level at 1 pixel vs level 4 $d_level; level 4 corrected vs not $d_correction"
awk -v d="$d_level" 'BEGIN { exit !(d > 2) }' || fail "level 4 looks like the whole mesh (RMSE $d_level)"
awk -v d="$d_correction" 'BEGIN { exit !(d > 0.5) }' || fail "the correction changes nothing (RMSE $d_correction)"
l1="$(logged_level auto1)"
l8="$(logged_level auto8)"
note "automatic level: $l1 at 1 pixel, $l8 at 8 pixels"
[ -n "$l1" ] && [ -n "$l8" ] || fail "no automatic level logged"
[ $((l1 - l8)) -eq 3 ] || fail "automatic levels $l1 (1 px) and $l8 (8 px) are not 3 apart"
note "ok"
