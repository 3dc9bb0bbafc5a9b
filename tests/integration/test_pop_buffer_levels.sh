#!/usr/bin/env bash
# "Extract Level of Detail (POP Buffer)" through the real meshlabserver 2020.09: a tilted, textured
# plane (wedge coordinates) written at levels 2, 3 and 4 as new layers, saved with the project (-w);
# check_pop_levels.py recomputes the grid, the kept triangles and the corrected coordinates. Then
# the refusals: no texture coordinates with the correction on, a level out of range; the layer is
# saved unchanged.
source "$(dirname "$0")/lib.sh"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_pop_levels.py"
FILTER="Extract Level of Detail (POP Buffer)"

pop_mlx() {  # FILE LEVELS CORRECTION
    filter_script "$1" "$FILTER" \
        "levels=$2" \
        "correction=$3"
}

$CHECK make "$WORK/plane.ply"
pop_mlx "$WORK/levels.mlx" "2-4" true
mkdir -p "$WORK/out"
run_meshlabserver "$WORK/levels.log" -i "$WORK/plane.ply" -s "$WORK/levels.mlx" -w "$WORK/out/levels.mlp" \
    || { cat "$WORK/levels.log" >&2; fail "the filter failed"; }
for level in 2 3 4; do
    grep -qE "level $level \(grid of $((1 << level)) cells per axis\) -> layer 'plane_pop$level': [0-9]+ of 450 triangles, [0-9]+ vertices, [0-9]+ moved" \
        "$WORK/levels.log" || { cat "$WORK/levels.log" >&2; fail "no log line for level $level"; }
    [ -s "$WORK/out/plane_pop${level}_out.ply" ] || { ls "$WORK/out" >&2; fail "layer of level $level not saved"; }
    $CHECK check "$WORK/out/plane_pop${level}_out.ply" "$level" || fail "level $level is wrong"
done

# Refusals: the layer is saved unchanged (expect_refusal compares with a plain load and save).
python3 - "$WORK" <<'PY'
import sys
with open(sys.argv[1] + "/untextured.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
            "0 0 0\n1 0 0\n1 1 0.5\n0 1 0.5\n3 0 1 2\n3 0 2 3\n")
PY
expect_refusal no_texcoords "has no texture coordinates to correct" "$WORK/untextured.ply" "$WORK/levels.mlx"
pop_mlx "$WORK/level17.mlx" "17" false
expect_refusal level_17 "Level 17 does not exist" "$WORK/untextured.ply" "$WORK/level17.mlx"
note "ok"
