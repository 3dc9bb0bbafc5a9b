#!/usr/bin/env bash
# "Compute Irradiance Vector Grid" through the real meshlabserver 2020.09: a column on its ground lit
# by a directional light; the grid is written beside the layer's file (empty output path: the
# convention the decoration relies on) and at a given path, and read back by check_ivg.py (an
# independent reader). Then the refusals: no environment map file, a missing one, a resolution of 0;
# the layer is saved unchanged and no .ivg file appears.
source "$(dirname "$0")/lib.sh"
FILTER="Compute Irradiance Vector Grid"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_ivg.py"

ivg_mlx() {  # FILE LIGHT(0 map, 1 sun) ENVMAP RESOLUTION OUTPUT
    filter_script "$1" "$FILTER" \
        "resolution=$4" \
        bounces=2 \
        rays=16 \
        "lightSource=$2" \
        "envMap=$3" \
        lightCount=16 \
        envScale=1 \
        lightDirection=0.3,0.2,1 \
        lightIrradiance=1 \
        "outputFile=$5"
}

"$MAKE_SCENE" column -o "$WORK/column.ply" >/dev/null

# Beside the layer's file.
ivg_mlx "$WORK/beside.mlx" 1 "" 6 ""
run_meshlabserver "$WORK/beside.log" -i "$WORK/column.ply" -s "$WORK/beside.mlx" \
    || { cat "$WORK/beside.log" >&2; fail "the filter failed"; }
[ -s "$WORK/column.ivg" ] || { cat "$WORK/beside.log" >&2; fail "no column.ivg beside column.ply"; }
grep -qE "Compute Irradiance Vector Grid: [0-9]+ x [0-9]+ x [0-9]+ cells, [0-9]+ grid vertices" "$WORK/beside.log" \
    || { cat "$WORK/beside.log" >&2; fail "no grid size in the log"; }
grep -qE "grid vertices inside objects or behind walls" "$WORK/beside.log" || fail "no repaired-vertex count in the log"
$CHECK "$WORK/column.ivg" 0.05 || fail "column.ivg is wrong"

# At a given path, lit by an environment map.
ENVMAP="$RADIANCE_SOURCE_DIR/data-cache/hdr/preview_studio.hdr"
if [ -f "$ENVMAP" ]; then
    mkdir -p "$WORK/out"
    ivg_mlx "$WORK/given.mlx" 0 "$ENVMAP" 4 "$WORK/out/grid.ivg"
    run_meshlabserver "$WORK/given.log" -i "$WORK/column.ply" -s "$WORK/given.mlx" \
        || { cat "$WORK/given.log" >&2; fail "the filter failed with an environment map"; }
    $CHECK "$WORK/out/grid.ivg" 0.05 || fail "out/grid.ivg is wrong"
    grep -qF "median-cut lights of preview_studio.hdr" "$WORK/given.log" || fail "the log does not name the map"
else
    note "no $ENVMAP: environment-map case skipped"
fi

# Refusals: the layer unchanged, no file written.
mkdir -p "$WORK/refused"
cp "$WORK/column.ply" "$WORK/refused/column.ply"
ivg_mlx "$WORK/nomap.mlx" 0 "" 6 ""
expect_refusal no_map "No environment map given" "$WORK/refused/column.ply" "$WORK/nomap.mlx"
ivg_mlx "$WORK/missing.mlx" 0 "$WORK/does_not_exist.exr" 6 ""
expect_refusal missing_map "does_not_exist.exr" "$WORK/refused/column.ply" "$WORK/missing.mlx"
ivg_mlx "$WORK/zero.mlx" 1 "" 0 ""
expect_refusal zero_resolution "The grid resolution is 0 cells" "$WORK/refused/column.ply" "$WORK/zero.mlx"
[ ! -e "$WORK/refused/column.ivg" ] || fail "a refused filter wrote a grid"
note "ok"
