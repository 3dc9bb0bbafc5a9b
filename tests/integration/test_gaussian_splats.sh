#!/usr/bin/env bash
# "Transfer Radiance from Gaussian Splats" through the real meshlabserver 2020.09: a view-dependent
# SH1 splat field on the unit sphere (written by splat_writer.py in the reference implementation's
# layout) transferred onto a UV sphere, vertex colours within 3 8-bit levels of the field's hemisphere
# mean computed in numpy (splat_writer.expected_mean_colors), the radiance saved as SH1; and the bad
# inputs refused with their message, the layer saved unchanged after the refusal.
source "$(dirname "$0")/lib.sh"
WRITER="$RADIANCE_SOURCE_DIR/tests/integration/splat_writer.py"
for scenario in sphere_mesh sphere_splats nan degree4 far; do
    python3 "$WRITER" "$scenario" "$WORK/$scenario.ply"
done

# splats_mlx FILE SPLATFILE: the filter with every parameter listed (meshlabserver needs them all).
splats_mlx() {
    filter_script "$1" "Radiance: Transfer Radiance from Gaussian Splats" \
        "splatfile=$2" \
        maxSplatSize=10 \
        frontTolerance=1 \
        setColor=true
}

splats_mlx "$WORK/good.mlx" "$WORK/sphere_splats.ply"
run_meshlabserver "$WORK/good.log" -i "$WORK/sphere_mesh.ply" -s "$WORK/good.mlx" -o "$WORK/good.rply" -m vc vn \
    || { cat "$WORK/good.log" >&2; fail "the transfer failed"; }
grep -qF "Transferred SH1 radiance functions onto" "$WORK/good.log" || { cat "$WORK/good.log" >&2; fail "no transfer log line"; }
python3 - "$WORK/good.rply" "$RADIANCE_SOURCE_DIR/tests/integration" <<'PY' || fail "transferred colours or radiance wrong"
import sys
sys.path.insert(0, sys.argv[2])
import numpy as np
import ply_reader, splat_writer
ply = ply_reader.read_ply(sys.argv[1])
v = ply["elements"]["vertex"]
points = np.stack([np.array(v[a], dtype=float) for a in ("x", "y", "z")], axis=1)
got = np.stack([np.array(v[c], dtype=float) for c in ("red", "green", "blue")], axis=1)
expected = splat_writer.expected_mean_colors(points, points / np.linalg.norm(points, axis=1, keepdims=True))
error = np.abs(got - expected).mean()
print(f"meshlabserver: mean colour error {error:.2f} levels, worst {np.abs(got - expected).max():.0f}")
assert error <= 3.0, error
assert any("SH1" in c for c in ply["comments"]), ply["comments"]
assert "rf_r_3" in v and "rf_r_4" not in v
PY

splats_mlx "$WORK/not_splat.mlx" "$WORK/sphere_mesh.ply"
expect_refusal not_a_splat_file "not a 3D Gaussian splat file" "$WORK/sphere_mesh.ply" "$WORK/not_splat.mlx"
splats_mlx "$WORK/nan.mlx" "$WORK/nan.ply"
expect_refusal nan "not a finite number" "$WORK/sphere_mesh.ply" "$WORK/nan.mlx"
splats_mlx "$WORK/degree4.mlx" "$WORK/degree4.ply"
expect_refusal degree4 "spherical harmonics are of degree 4" "$WORK/sphere_mesh.ply" "$WORK/degree4.mlx"
splats_mlx "$WORK/missing.mlx" "$WORK/no_such_folder/splats.ply"
expect_refusal missing_folder "cannot be opened" "$WORK/sphere_mesh.ply" "$WORK/missing.mlx"
splats_mlx "$WORK/far.mlx" "$WORK/far.ply"
expect_refusal far "no vertex of the mesh has a splat near it" "$WORK/sphere_mesh.ply" "$WORK/far.mlx"
note "ok"
