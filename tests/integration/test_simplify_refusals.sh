#!/usr/bin/env bash
# "Radiance-Aware Simplification" on bad input, through the real meshlabserver: a clear message in
# the log, no crash, and the layer saved unchanged:
#  - a mesh without radiance data (radiance metric); - a target not below the face count;
#  - a non-manifold edge (three faces on one edge) with a free boundary; - a point cloud.
# A non-manifold edge with a preserved boundary is kept as it is and counted in the log.
# A repeated face is not refused: it is removed, counted in the log, and the rest simplified.
source "$(dirname "$0")/lib.sh"
TOOLS="$RADIANCE_BUILD_DIR/tools"
WRITE_MLX="bash $RADIANCE_SOURCE_DIR/scripts/write_simplify_mlx.sh"

"$MAKE_SCENE" sphere --level 2 -o "$WORK/sphere.ply"
"$TOOLS/make_radiance_mesh" "$WORK/sphere.ply" --basis PB2 --no-shadows -o "$WORK/sphere.rply" >/dev/null 2>&1 \
    || fail "make_radiance_mesh failed"
$WRITE_MLX "$WORK/half.mlx" 0.5

expect_refusal no_radiance "The current mesh has no radiance data" "$WORK/sphere.ply" "$WORK/half.mlx"
$WRITE_MLX "$WORK/everything.mlx" 0.999999
edit_mlx "$WORK/half.mlx" "$WORK/target.mlx" targetFaces=100000 targetPercentage=0
expect_refusal target_too_large "is not below the layer's" "$WORK/sphere.rply" "$WORK/target.mlx"

# ASCII PLY variants of the radiance-free sphere (geometry-only metric, so radiance is not the issue).
$WRITE_MLX "$WORK/geometry.mlx" 0.5 3
python3 - "$WORK" <<'PY'
import sys
work = sys.argv[1]
def write(name, vertices, faces):
    with open(f"{work}/{name}.ply", "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                % len(vertices))
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for v in vertices:
            f.write("%g %g %g\n" % v)
        for t in faces:
            f.write("3 %d %d %d\n" % t)
# A 2 x 8 grid of quads (7 interior vertices), then two more faces on the edge (0, 1): three faces
# on one edge, a non-manifold edge.
verts = [(x, y, 0.0) for y in (0, 1, 2) for x in range(9)]
faces = []
for y in range(2):
    for x in range(8):
        a, b, c, d = 9 * y + x, 9 * y + x + 1, 9 * (y + 1) + x + 1, 9 * (y + 1) + x
        faces += [(a, b, c), (a, c, d)]
write("strip", verts, faces)
write("nonmanifold", verts + [(0.5, -0.5, 1.0), (0.5, -0.5, -1.0)], faces + [(1, 0, 27), (0, 1, 28)])
write("duplicate", verts, faces + [faces[3]])
write("points", verts, [])
PY
# A non-manifold edge: refused with a free boundary (naming both fixes), kept as it is with a preserved one.
edit_mlx "$WORK/geometry.mlx" "$WORK/geometry_free.mlx" preserveBoundary=false
expect_refusal nonmanifold "turn 'Preserve boundary' on, or run 'Cleaning and Repairing: Repair non Manifold Edges'" \
    "$WORK/nonmanifold.ply" "$WORK/geometry_free.mlx"
run_meshlabserver "$WORK/nonmanifold.log" -i "$WORK/nonmanifold.ply" -s "$WORK/geometry.mlx" -o "$WORK/nonmanifold.out.ply" \
    || { cat "$WORK/nonmanifold.log" >&2; fail "the strip with a non-manifold edge failed"; }
grep -qF "Non-manifold edges: 1 (more than two faces), kept as they are with their vertices" "$WORK/nonmanifold.log" \
    || { cat "$WORK/nonmanifold.log" >&2; fail "the non-manifold edge is not in the log"; }
expect_refusal point_cloud "has no faces" "$WORK/points.ply" "$WORK/geometry.mlx"
# The clean strip (with boundary) simplifies as far as its boundary allows.
run_meshlabserver "$WORK/strip.log" -i "$WORK/strip.ply" -s "$WORK/geometry.mlx" -o "$WORK/strip.out.ply" \
    || { cat "$WORK/strip.log" >&2; fail "clean strip failed"; }
# Its 7 interior vertices go; the 20 boundary vertices stay (boundary preserved), and the log says
# why the target of 16 faces was not reached.
grep -qF "Simplified 32 -> 18 faces (20 vertices)" "$WORK/strip.log" || { cat "$WORK/strip.log" >&2; fail "no summary for the strip"; }
grep -qF "Stopped at 18 faces above the target of 16" "$WORK/strip.log" || { cat "$WORK/strip.log" >&2; fail "no warning for the unreached target"; }
# The same strip with one face twice: the copy is removed and counted, the result is the clean strip's.
run_meshlabserver "$WORK/duplicate.log" -i "$WORK/duplicate.ply" -s "$WORK/geometry.mlx" -o "$WORK/duplicate.out.ply" \
    || { cat "$WORK/duplicate.log" >&2; fail "the strip with a duplicate face failed"; }
grep -qF "1 duplicate faces removed" "$WORK/duplicate.log" || { cat "$WORK/duplicate.log" >&2; fail "duplicate not counted"; }
cmp -s "$WORK/duplicate.out.ply" "$WORK/strip.out.ply" || fail "the strip with a duplicate face did not simplify like the clean strip"

# Script mistakes meshlabserver passes through unchecked: an enum index beyond the choices (it used to
# be read as another metric), a NaN weight, a negative angle. Each is refused, naming the parameter.
edit_mlx "$WORK/half.mlx" "$WORK/metric9.mlx" metric=9
expect_refusal enum_out_of_range "The parameter 'metric' is 9, which is none of its choices: 0 = " \
    "$WORK/sphere.rply" "$WORK/metric9.mlx"
edit_mlx "$WORK/half.mlx" "$WORK/nan_weight.mlx" geometryWeight=nan
expect_refusal nan_weight "The parameter 'geometryWeight' is not a finite number" "$WORK/sphere.rply" "$WORK/nan_weight.mlx"
edit_mlx "$WORK/half.mlx" "$WORK/angle.mlx" maxNormalChange=-10
expect_refusal negative_angle "[0, 180] degrees (it is -10)" "$WORK/sphere.rply" "$WORK/angle.mlx"
note "refusals ok"
