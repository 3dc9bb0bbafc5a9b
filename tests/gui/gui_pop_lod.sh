#!/usr/bin/env bash
# GUI test of the POP-buffer level of detail of the "Baked Normal Map" decoration (Limper et al.
# 2013; texture-coordinate correction of Weber & Stamminger, Alg. 1) in Debian's real meshlab under
# Xvfb. The armadillo is simplified by MeshLab (Quadric Edge Collapse, 1,000 faces) and baked by our
# filter, as in gui_normal_map.sh; a second meshlabserver run writes level 4 on the CPU with our
# "Extract Level of Detail (POP Buffer)" filter (correction on). meshlab then opens a project of both
# layers (the same bounding box, hence the same view after Ctrl+H) four times, with private
# settings: the baked layer with level 4 forced (the vertex shader's level), the CPU level with the
# level of detail off (its reference), and the baked layer at the automatic level for tolerances of
# 1 and 8 pixels (about a minute). Asserts
#   - the forced level's log line gives the triangle count recomputed here in Python from the saved
#     layer (triangles whose three corners are in three different cells of the 16^3 grid), and the
#     filter's layer has that many faces,
#   - the decoration's level 4 matches the CPU-evaluated level 4 on pixels (RMSE below 3 levels),
#     and differs from the automatic level at 1 pixel (level 9 here),
#   - the automatic level at 8 pixels is 3 below the one at 1 pixel (2^3 = 8: the level keeps the
#     snapping within the tolerance), at the same view,
#   - no GL error.
source "$(dirname "$0")/../integration/lib.sh"
source "$(dirname "$0")/gui_lib.sh"
bake_armadillo 512

# Level 4 on the CPU (the filter), saved with the baked layer as a project.
filter_script "$WORK/extract.mlx" "Extract Level of Detail (POP Buffer)" \
    levels=4 correction=true
run_meshlabserver "$WORK/extract.log" -i "$WORK/armadillo_baked.ply" -s "$WORK/extract.mlx" -w "$WORK/lod.mlp" \
    || { cat "$WORK/extract.log" >&2; fail "the level-4 layer could not be written"; }
[ -s "$WORK/armadillo_baked_pop4_out.ply" ] || fail "no level-4 layer saved"
# Two projects of the same two layers: the one drawn last is the current layer, the other hidden.
project() {  # project FILE VISIBLE_PLY CURRENT_PLY(shown)
    {
        echo '<!DOCTYPE MeshLabDocument>'
        echo '<MeshLabProject>'
        echo ' <MeshGroup>'
        printf '  <MLMesh label="%s" filename="%s" visible="0">\n   <MLMatrix44>\n1 0 0 0 \n0 1 0 0 \n0 0 1 0 \n0 0 0 1 \n</MLMatrix44>\n  </MLMesh>\n' "$2" "$2"
        printf '  <MLMesh label="%s" filename="%s" visible="1">\n   <MLMatrix44>\n1 0 0 0 \n0 1 0 0 \n0 0 1 0 \n0 0 0 1 \n</MLMatrix44>\n  </MLMesh>\n' "$3" "$3"
        echo ' </MeshGroup>'
        echo ' <RasterGroup/>'
        echo '</MeshLabProject>'
    } >"$1"
}
project "$WORK/gpu.mlp" armadillo_baked_pop4_out.ply armadillo_baked_out.ply
project "$WORK/cpu.mlp" armadillo_baked_out.ply armadillo_baked_pop4_out.ply

# Triangles of level 4 (16 cells per axis over the bounding box), from the saved layer.
expected="$(python3 - "$WORK/armadillo_baked.ply" "$WORK/armadillo_baked_pop4_out.ply" <<'PY'
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
print(kept, len(ply.data["face"]["vertex_indices"]), len(read_ply(sys.argv[2]).data["face"]["vertex_indices"]))
PY
)"
read -r kept total filtered <<<"$expected"
note "level 4 keeps $kept of $total triangles (computed here); the filter's layer has $filtered"
[ "$kept" = "$filtered" ] || fail "the filter's level-4 layer has $filtered faces, not $kept"

start_xvfb
setting() {  # setting TYPE NAME VALUE [EXTRA]
    printf 'MeshLab%%3A%%3ADecoration%%3A%%3A%s="<!DOCTYPE MeshLabSettings>\\n<Param type=\\"%s\\" value=\\"%s\\" name=\\"MeshLab::Decoration::%s\\"%s/>\\n"\n' \
        "$2" "$1" "$3" "$2" "${4:-}"
}
shot() {  # shot NAME PROJECT LOD(0|1|2) LEVEL CORRECTION TOLERANCE
    local name="$1"
    mkdir -p "$XDG_CONFIG_HOME/VCG"
    {
        echo '[General]'
        setting RichEnum NormalMapShading 1 ' enum_cardinality=\"3\" enum_val0=\"a\" enum_val1=\"b\" enum_val2=\"c\"'
        setting RichEnum NormalMapLevelOfDetail "$3" ' enum_cardinality=\"3\" enum_val0=\"a\" enum_val1=\"b\" enum_val2=\"c\"'
        setting RichInt NormalMapLevelOfDetailLevel "$4"
        setting RichBool NormalMapLevelOfDetailCorrection "$5"
        setting RichFloat NormalMapLevelOfDetailTolerance "$6"
    } >"$XDG_CONFIG_HOME/VCG/MeshLab_64bit_fp.conf"
    start_meshlab "$name" "$2"
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
    # The 3D view's place on screen (its width follows the layer panel's, which varies from run to
    # run): the tallest child window at the left edge, below the toolbars. "WIDTH TOP".
    xwininfo -tree -id "$window" | awk '
        NF >= 2 { abs = $NF; geo = $(NF - 1) }
        NF < 2 { next }
        abs ~ /^\+0\+[0-9]+$/ && geo ~ /^[0-9]+x[0-9]+\+/ {
            split(geo, g, /[x+]/); split(abs, a, /\+/)
            if (a[3] >= 50 && g[2] > best) { best = g[2]; w = g[1]; top = a[3] }
        }
        END { if (best > 0) print w, top }' >"$WORK/$name.view"
    [ -s "$WORK/$name.view" ] || fail "$name: the 3D view was not found among MeshLab's windows"
    stop_meshlab
    if grep -n "GL error" "$WORK/$name.meshlab.log"; then fail "$name: GL error"; fi
    grep -qF "Baked Normal Map: layer" "$WORK/$name.meshlab.log" \
        || { tail -n 30 "$WORK/$name.meshlab.log" >&2; fail "$name: the decoration did not start"; }
}
box() {  # the 400 x 560 box centred on the 3D view of shot NAME, below the real-time info box at its top
    awk '{ printf "400x560+%d+%d", $1 / 2 - 200, $2 + 100 }' "$WORK/$1.view"
}
rmse() {  # rmse NAME NAME: the two shots' boxes (the view is framed on its centre: Ctrl+H)
    convert "$WORK/$1.png" -crop "$(box "$1")" +repage "$WORK/$1.box.png"
    convert "$WORK/$2.png" -crop "$(box "$2")" +repage "$WORK/$2.box.png"
    { compare -metric RMSE "$WORK/$1.box.png" "$WORK/$2.box.png" null: 2>&1 || true; } |
        sed -E 's/.*\(([0-9.e-]+)\).*/\1/' | awk '{ printf "%.2f", $1 * 255 }'
}
logged_level() {  # the last POP level the decoration logged
    grep -oE "Baked Normal Map: POP level [0-9]+" "$WORK/$1.meshlab.log" | tail -n 1 | awk '{ print $NF }'
}

shot gpu "$WORK/gpu.mlp" 2 4 true 1
shot cpu "$WORK/cpu.mlp" 0 4 true 1
shot auto1 "$WORK/gpu.mlp" 1 4 true 1
shot auto8 "$WORK/gpu.mlp" 1 4 true 8

grep -qF "Baked Normal Map: layer 'armadillo_baked_out.ply'" "$WORK/gpu.meshlab.log" || fail "gpu: not the baked layer"
grep -qF "Baked Normal Map: layer 'armadillo_baked_pop4_out.ply'" "$WORK/cpu.meshlab.log" || fail "cpu: not the level-4 layer"
grep -qF "Baked Normal Map: POP level 4 (forced, texture coordinates corrected): $kept of $total triangles" \
    "$WORK/gpu.meshlab.log" || { grep "POP level" "$WORK/gpu.meshlab.log" >&2; fail "no log line with $kept of $total triangles"; }
d_cpu="$(rmse gpu cpu)"
d_level="$(rmse gpu auto1)"
note "RMSE (8-bit levels): decoration's level 4 vs the CPU-evaluated level 4 $d_cpu; vs the automatic level at 1 pixel $d_level"
awk -v d="$d_cpu" 'BEGIN { exit !(d < 3) }' || fail "the decoration's level 4 differs from the CPU's (RMSE $d_cpu)"
awk -v d="$d_level" 'BEGIN { exit !(d > 2) }' || fail "level 4 looks like the automatic level at 1 pixel (RMSE $d_level)"
l1="$(logged_level auto1)"
l8="$(logged_level auto8)"
note "automatic level: $l1 at 1 pixel, $l8 at 8 pixels"
[ -n "$l1" ] && [ -n "$l8" ] || fail "no automatic level logged"
[ $((l1 - l8)) -eq 3 ] || fail "automatic levels $l1 (1 px) and $l8 (8 px) are not 3 apart"
note "ok"
