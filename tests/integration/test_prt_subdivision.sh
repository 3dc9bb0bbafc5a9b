#!/usr/bin/env bash
# The PRT filters through the real meshlabserver on Křivánek et al. 2004's column-on-plane scene:
#  - "Compute PRT Transfer": ground vertices' transfer matches a brute-force geometric visibility
#    computed in Python; the .rply keeps the transfer (save -> reload -> save is bit-identical);
#  - "Adaptive PRT Subdivision" (4x budget): conforming output (no T-junctions), surface unchanged,
#    budget respected, refined near the column, new vertices ray-cast (the same geometric check
#    on the subdivided ground), face quality written;
#  - "Uniform PRT Subdivision": exactly 4x the faces;
#  - "PRT Relighting as Vertex Color": a directional light casts the column's shadow on the
#    ground; an HDR environment map relights without error.
source "$(dirname "$0")/lib.sh"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_prt.py"
SAME="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_radiance_ply.py same"
MLX="bash $RADIANCE_SOURCE_DIR/scripts/write_prt_mlx.sh"

"$MAKE_SCENE" column -o "$WORK/column.ply"
faces=$(python3 -c "import sys; sys.path.insert(0, sys.argv[1]); from ply_reader import read_ply; print(len(read_ply(sys.argv[2]).data['face']['vertex_indices']))" \
    "$RADIANCE_SOURCE_DIR/tests/integration" "$WORK/column.ply")

$MLX "$WORK/transfer.mlx" transfer:6:256
run_meshlabserver "$WORK/transfer.log" -i "$WORK/column.ply" -s "$WORK/transfer.mlx" -o "$WORK/transfer.rply" -m vc vn \
    || { cat "$WORK/transfer.log" >&2; fail "Compute PRT Transfer failed"; }
grep -q "Computed PRT transfer" "$WORK/transfer.log" || fail "no log line of the transfer filter"
$CHECK column-transfer "$WORK/transfer.rply"
run_meshlabserver "$WORK/reload.log" -i "$WORK/transfer.rply" -o "$WORK/reload.rply" -m vc vn || fail "reload failed"
grep -q "^comment block prt width 36" <(head -c 4000 "$WORK/reload.rply" | tr -d '\r') || fail "transfer not reloaded and saved"
$SAME "$WORK/transfer.rply" "$WORK/reload.rply" || fail "save -> reload -> save changed the file"

$MLX "$WORK/adaptive.mlx" adaptive:4
run_meshlabserver "$WORK/adaptive.log" -i "$WORK/transfer.rply" -s "$WORK/adaptive.mlx" \
    -o "$WORK/adaptive.rply" -m vc vn -o "$WORK/adaptive.ply" -m vc vn fq fc \
    || { cat "$WORK/adaptive.log" >&2; fail "Adaptive PRT Subdivision failed"; }
grep "Adaptive PRT subdivision" "$WORK/adaptive.log" | head -n 1
$CHECK conforming "$WORK/adaptive.rply" $((faces + 1)) $((4 * faces))
$CHECK refined-near-column "$WORK/adaptive.rply"
$CHECK column-transfer "$WORK/adaptive.rply"
$CHECK face-quality "$WORK/adaptive.ply"

$MLX "$WORK/uniform.mlx" uniform:4
run_meshlabserver "$WORK/uniform.log" -i "$WORK/transfer.rply" -s "$WORK/uniform.mlx" -o "$WORK/uniform.rply" -m vc vn \
    || { cat "$WORK/uniform.log" >&2; fail "Uniform PRT Subdivision failed"; }
$CHECK conforming "$WORK/uniform.rply" $((4 * faces)) $((4 * faces))

$MLX "$WORK/relight.mlx" relight-dir:1:0.3:0.8:3
run_meshlabserver "$WORK/relight.log" -i "$WORK/adaptive.rply" -s "$WORK/relight.mlx" -o "$WORK/relit.ply" -m vc \
    || { cat "$WORK/relight.log" >&2; fail "relighting failed"; }
$CHECK shadowed "$WORK/relit.ply" 1 0.3 0.8

hdr=$(ls "$RADIANCE_SOURCE_DIR"/data-cache/hdr/*.exr "$RADIANCE_SOURCE_DIR"/data-cache/hdr/*.hdr 2>/dev/null | head -n 1 || true)
[ -n "$hdr" ] || fail "no HDR map in data-cache/hdr (the test command fetches them)"
$MLX "$WORK/env.mlx" "relight-env:$hdr:90:2"
run_meshlabserver "$WORK/env.log" -i "$WORK/adaptive.rply" -s "$WORK/env.mlx" -o "$WORK/env.ply" -m vc \
    || { cat "$WORK/env.log" >&2; fail "environment relighting failed"; }
grep -q "Relit .* under the environment map" "$WORK/env.log" || { cat "$WORK/env.log" >&2; fail "no env relight log"; }
note "all PRT filter checks passed"
