#!/usr/bin/env bash
# "Radiance: Radiance-Aware Simplification" through the real meshlabserver on a radiance sphere
# (PB4 of the striped glossy sample material, 10,242 vertices):
#  - simplified to 25 % with two extra level-of-detail layers and a progressive mesh file: the layer
#    saved is a closed oriented manifold with the target face count, made of original vertices that
#    kept their own radiance rows (checked in Python, independently of the C++ code);
#  - the progressive file replayed by the simplify_radiance tool gives exactly the same faces;
#  - the colour-QEM and full-collapse variants run; full collapse on a PB field is refused.
source "$(dirname "$0")/lib.sh"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_simplification.py"
TOOLS="$RADIANCE_BUILD_DIR/tools"
WRITE_MLX="bash $RADIANCE_SOURCE_DIR/scripts/write_simplify_mlx.sh"

"$MAKE_SCENE" sphere --level 5 -o "$WORK/sphere.ply"
"$TOOLS/make_radiance_mesh" "$WORK/sphere.ply" --material stripes --basis PB4 --no-shadows -o "$WORK/sphere.rply" \
    >"$WORK/make.log" 2>&1 || { cat "$WORK/make.log" >&2; fail "make_radiance_mesh failed"; }
faces=$(grep -a -m1 "^element face" "$WORK/sphere.rply" | awk '{print $3}')
target=$((faces / 4))

$WRITE_MLX "$WORK/simplify.mlx" 0.25 0 "0.5 0.1" "$WORK/sphere.rpm"
run_meshlabserver "$WORK/simplify.log" -i "$WORK/sphere.rply" -s "$WORK/simplify.mlx" -o "$WORK/simplified.rply" \
    || { cat "$WORK/simplify.log" >&2; fail "simplification failed"; }
grep -qF "Simplified $faces -> $target faces" "$WORK/simplify.log" || { cat "$WORK/simplify.log" >&2; fail "no summary line"; }
grep -qF "Level of detail 50 %" "$WORK/simplify.log" || fail "no 50 % level of detail layer"
grep -qF "Level of detail 10 %" "$WORK/simplify.log" || fail "no 10 % level of detail layer"
$CHECK halfedge "$WORK/sphere.rply" "$WORK/simplified.rply" "$target" "$((target - 1))" || fail "bad simplified mesh"
[ -s "$WORK/sphere.rpm" ] && [ -s "$WORK/sphere_base.rply" ] || fail "no progressive mesh written"

"$TOOLS/simplify_radiance" "$WORK/sphere.rpm" -o "$WORK/replay" --ratios 0.25,0.1 >"$WORK/replay.log" 2>&1 \
    || { cat "$WORK/replay.log" >&2; fail "replay failed"; }
$CHECK samefaces "$WORK/simplified.rply" "$WORK/replay_250.rply" || fail "the replayed 25 % level differs from the layer"
$CHECK halfedge "$WORK/sphere.rply" "$WORK/replay_100.rply" "$((faces / 10))" "$((faces / 10 - 1))" || fail "bad 10 % level"

# The colour baseline and the geometry-only metric run in the same engine.
$WRITE_MLX "$WORK/color.mlx" 0.25 2
run_meshlabserver "$WORK/color.log" -i "$WORK/sphere.rply" -s "$WORK/color.mlx" -o "$WORK/color.rply" \
    || { cat "$WORK/color.log" >&2; fail "colour QEM failed"; }
$CHECK halfedge "$WORK/sphere.rply" "$WORK/color.rply" "$target" "$((target - 1))" || fail "bad colour-QEM mesh"

# Full edge collapse needs SH with the radiance metric: refused on PB, layer unchanged.
$WRITE_MLX "$WORK/full.mlx" 0.25 0 "" "" 1
run_meshlabserver "$WORK/full_pb.log" -i "$WORK/sphere.rply" -s "$WORK/full.mlx" -o "$WORK/full_pb.rply" || true
grep -qF "full edge collapse with the radiance metric needs spherical harmonics" "$WORK/full_pb.log" \
    || { cat "$WORK/full_pb.log" >&2; fail "no refusal of full collapse on PB"; }
if [ -e "$WORK/full_pb.rply" ]; then
    python3 "$RADIANCE_SOURCE_DIR/tests/integration/check_radiance_ply.py" same "$WORK/sphere.rply" "$WORK/full_pb.rply" \
        || fail "the refused filter changed the layer"
fi
"$TOOLS/make_radiance_mesh" "$WORK/sphere.ply" --material glossy --basis SH4 --no-shadows -o "$WORK/sphere_sh.rply" \
    >"$WORK/make_sh.log" 2>&1 || fail "make_radiance_mesh SH failed"
run_meshlabserver "$WORK/full_sh.log" -i "$WORK/sphere_sh.rply" -s "$WORK/full.mlx" -o "$WORK/full_sh.rply" \
    || { cat "$WORK/full_sh.log" >&2; fail "full collapse on SH failed"; }
grep -qF "full edge collapse" "$WORK/full_sh.log" || { cat "$WORK/full_sh.log" >&2; fail "no full-collapse summary"; }
note "simplification, levels of detail, replay and variants ok"
