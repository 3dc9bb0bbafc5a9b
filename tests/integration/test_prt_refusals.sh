#!/usr/bin/env bash
# The PRT filters on bad input, through the real meshlabserver: a clear message in the log, no
# crash, the layer saved unchanged:
#  - subdivision without transfer vectors; - a budget below the face count; - a non-manifold edge;
#  - zero-area triangles; - transfer on vertices without normals (a point cloud);
#  - subdividing an albedo (3-channel) transfer; - a missing environment map file.
# And an open mesh (a lone ground plane: every ray escapes) gets the unoccluded transfer, which
# is right: band 0 = Y00 at every vertex.
source "$(dirname "$0")/lib.sh"
MLX="bash $RADIANCE_SOURCE_DIR/scripts/write_prt_mlx.sh"

"$MAKE_SCENE" column --ground 2 -o "$WORK/column.ply"
$MLX "$WORK/transfer.mlx" transfer:3:16
run_meshlabserver "$WORK/transfer.log" -i "$WORK/column.ply" -s "$WORK/transfer.mlx" -o "$WORK/column.rply" -m vc vn \
    || { cat "$WORK/transfer.log" >&2; fail "transfer failed"; }

$MLX "$WORK/adaptive.mlx" adaptive:4
expect_refusal no_transfer "has no PRT transfer vectors" "$WORK/column.ply" "$WORK/adaptive.mlx"
$MLX "$WORK/small_budget.mlx" adaptive:0:2:1:0:100
expect_refusal budget_below "is below the layer's" "$WORK/column.rply" "$WORK/small_budget.mlx"

python3 - "$WORK" <<'PY'
import sys
work = sys.argv[1]
def write(name, vertices, faces, normals=True):
    with open(f"{work}/{name}.ply", "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                % len(vertices))
        if normals:
            f.write("property float nx\nproperty float ny\nproperty float nz\n")
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for v in vertices:
            f.write("%g %g %g%s\n" % (v + (" 0 0 1" if normals else "",)))
        for t in faces:
            f.write("3 %d %d %d\n" % t)
grid = [(x, y, 0.0) for y in range(4) for x in range(4)]
faces = []
for y in range(3):
    for x in range(3):
        a, b, c, d = 4 * y + x, 4 * y + x + 1, 4 * (y + 1) + x + 1, 4 * (y + 1) + x
        faces += [(a, b, c), (a, c, d)]
write("plane", grid, faces)
# Three faces on the edge (0, 1): a fin below the plane.
write("nonmanifold", grid + [(0.5, -1.0, 0.0)], faces + [(0, 1, 16), (1, 0, 16)])
# A zero-area face: three collinear vertices appended.
write("zero_area", grid + [(4.0, 0.0, 0.0), (5.0, 0.0, 0.0), (6.0, 0.0, 0.0)], faces + [(16, 17, 18)])
# A point cloud without normals.
with open(f"{work}/points.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nend_header\n")
    f.write("0 0 0\n1 0 0\n0 1 0\n1 1 1\n")
PY

# An open plane: the transfer is computed (rays escape) and every vertex is unoccluded.
$MLX "$WORK/transfer256.mlx" transfer:3:256
run_meshlabserver "$WORK/plane.log" -i "$WORK/plane.ply" -s "$WORK/transfer256.mlx" -o "$WORK/plane.rply" -m vn \
    || { cat "$WORK/plane.log" >&2; fail "transfer on an open plane failed"; }
python3 - "$RADIANCE_SOURCE_DIR/tests/integration" "$WORK/plane.rply" <<'PY' || fail "open plane: wrong transfer"
import math, sys
sys.path.insert(0, sys.argv[1])
from ply_reader import read_ply
v = read_ply(sys.argv[2]).data['vertex']
y00 = 0.5 / math.sqrt(math.pi)
bad = [i for i, t in enumerate(v['prt_0']) if abs(t - y00) > 1e-5]
if bad:
    sys.exit("vertices %s: band 0 is not Y00 = %.6f on an unoccluded plane" % (bad[:5], y00))
# Band 1 of a vertical normal: only Y_1^0 (index 2) is non-zero, = 2/3 * 0.4886 (the clamped cosine's);
# 256 low-discrepancy rays estimate it within 0.02.
z = [t for t in v['prt_2']]
if any(abs(t - 2.0 / 3.0 * 0.4886025119029199) > 0.02 for t in z):
    sys.exit("band 1 of the unoccluded plane is off: %s" % z[:4])
print("open plane: %d vertices unoccluded, band 0 = Y00" % len(v['prt_0']))
PY

# Transfer first (it accepts these meshes), then the subdivision refuses them.
for name in nonmanifold zero_area; do
    run_meshlabserver "$WORK/$name.transfer.log" -i "$WORK/$name.ply" -s "$WORK/transfer.mlx" -o "$WORK/$name.rply" -m vn \
        || { cat "$WORK/$name.transfer.log" >&2; fail "transfer on $name failed"; }
done
expect_refusal nonmanifold "non-manifold edge (shared by more than two faces" "$WORK/nonmanifold.rply" "$WORK/adaptive.mlx"
expect_refusal zero_area "Zero Area" "$WORK/zero_area.rply" "$WORK/adaptive.mlx"
expect_refusal no_normals "vertices has a usable normal and there are no faces" "$WORK/points.ply" "$WORK/transfer.mlx"
$MLX "$WORK/albedo.mlx" transfer:3:16:0:true
run_meshlabserver "$WORK/albedo.log" -i "$WORK/column.ply" -s "$WORK/albedo.mlx" -o "$WORK/albedo.rply" -m vc vn \
    || { cat "$WORK/albedo.log" >&2; fail "transfer with albedo failed"; }
expect_refusal albedo "include the albedo" "$WORK/albedo.rply" "$WORK/adaptive.mlx"
$MLX "$WORK/missing_map.mlx" "relight-env:$WORK/no_such_map.exr:0:0"
expect_refusal missing_map "no_such_map.exr" "$WORK/column.rply" "$WORK/missing_map.mlx"
note "all refusals clear, layers unchanged"
