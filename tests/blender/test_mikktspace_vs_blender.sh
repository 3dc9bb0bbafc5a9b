#!/usr/bin/env bash
# Our MikkTSpace tangents (geometry/mikktspace_tangents.h) against the ones Blender computes for the
# same triangles, normals and UVs (Mesh.calc_tangents): a UV sphere, a torus with seams, a grid with
# mirrored UVs, a flat-shaded cube, an icosphere with zero-area UV triangles. Every tangent component within 1e-4, every sign equal. The
# per-vertex UV path is run on the mirrored grid too (each of its vertices has one UV and one normal).
# Blender is found as $BLENDER or on PATH (Debian's package `blender`, installed by scripts/setup.sh).
# Usage: test_mikktspace_vs_blender.sh   (RADIANCE_BUILD_DIR, RADIANCE_SOURCE_DIR from ctest)
set -euo pipefail
: "${RADIANCE_BUILD_DIR:?set by ctest}"
: "${RADIANCE_SOURCE_DIR:?set by ctest}"
BLENDER="${BLENDER:-$(command -v blender || true)}"
[ -n "$BLENDER" ] || { echo "FAIL: Blender not found: install Debian's 'blender' package (scripts/setup.sh does) or set BLENDER" >&2; exit 1; }
WORK="$RADIANCE_BUILD_DIR/tests/integration-work/mikktspace_vs_blender"
rm -rf "$WORK"; mkdir -p "$WORK"
HERE="$RADIANCE_SOURCE_DIR/tests/blender"
TOOL="$RADIANCE_BUILD_DIR/tools/mikktspace_tangents"

"$BLENDER" -b --factory-startup -noaudio --python-exit-code 1 -P "$HERE/export_blender_tangents.py" -- "$WORK" \
  > "$WORK/blender.log" 2>&1 || { cat "$WORK/blender.log" >&2; echo "FAIL: the Blender export failed" >&2; exit 1; }
for name in uv_sphere torus mirrored_grid flat_cube degenerate_uv_ico; do
  [ -s "$WORK/$name.mesh" ] || { echo "FAIL: Blender wrote no $name.mesh" >&2; exit 1; }
  "$TOOL" "$WORK/$name.mesh" > "$WORK/$name.ours" 2> "$WORK/$name.counts"
  python3 "$HERE/compare_tangents.py" "$WORK/$name.ours" "$WORK/$name.blender" "$name" 1e-4
done
# The per-vertex UV path (a PLY with texture_u / texture_v) gives Blender's tangents too.
"$TOOL" "$WORK/mirrored_grid.mesh" --per-vertex-uv > "$WORK/mirrored_grid.vertex.ours"
python3 "$HERE/compare_tangents.py" "$WORK/mirrored_grid.vertex.ours" "$WORK/mirrored_grid.blender" "mirrored_grid (per-vertex UVs)" 1e-4
# The mirrored grid must really have both signs (otherwise the case tests nothing).
for s in 1.0 -1.0; do
  awk -v s="$s" '$4 == s {n++} END {exit !(n > 0)}' "$WORK/mirrored_grid.blender" || { echo "FAIL: no sign $s in Blender's mirrored grid" >&2; exit 1; }
done
# The icosphere must really have triangles without UV derivatives and corners no group reaches.
grep -Eq ' [1-9][0-9]* triangles without UV derivatives' "$WORK/degenerate_uv_ico.counts" \
  || { echo "FAIL: the icosphere case has no zero-area UV triangle: $(cat "$WORK/degenerate_uv_ico.counts")" >&2; exit 1; }
awk '$1 == 1 && $2 == 0 && $3 == 0 && $4 == -1 {n++} END {exit !(n > 0)}' "$WORK/degenerate_uv_ico.blender" || { echo "FAIL: no default frame in the icosphere case" >&2; exit 1; }
echo "PASS: MikkTSpace tangents equal Blender's within 1e-4"
