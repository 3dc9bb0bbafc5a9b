#!/usr/bin/env bash
# Makes the GUI test's input with the real meshlabserver: a sphere with PB(4) radiance data of a
# red glossy material (vertex colour = the RF's mean colour), saved as .rply.
# Usage: make_gui_input.sh OUTPUT_DIR
source "$(dirname "$0")/../integration/lib.sh"
out="$1"
mkdir -p "$out"
"$MAKE_SCENE" sphere --level 4 -o "$WORK/sphere.ply"
create_radiance_mlx "$WORK/create.mlx" 0 4 false 0.5 0
run_meshlabserver "$WORK/server.log" -i "$WORK/sphere.ply" -o "$out/sphere.rply" -m vc vn -s "$WORK/create.mlx" \
    || { cat "$WORK/server.log" >&2; fail "meshlabserver could not create the GUI input"; }
[ -s "$out/sphere.rply" ] || fail "no GUI input written"
# PRT input: the column on its ground (Křivánek et al. 2004 Fig. 1) with order-4 transfer vectors.
"$MAKE_SCENE" column --ground 8 -o "$WORK/column.ply"
bash "$RADIANCE_SOURCE_DIR/scripts/write_prt_mlx.sh" "$WORK/prt.mlx" transfer:4:128
run_meshlabserver "$WORK/server_prt.log" -i "$WORK/column.ply" -o "$out/column_prt.rply" -m vc vn -s "$WORK/prt.mlx" \
    || { cat "$WORK/server_prt.log" >&2; fail "meshlabserver could not compute the PRT GUI input"; }
[ -s "$out/column_prt.rply" ] || fail "no PRT GUI input written"
note "ok"
