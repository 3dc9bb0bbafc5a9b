#!/usr/bin/env bash
# The radiance data follows MeshLab's own edits: after creating it, Debian's filters select half of
# the vertices, delete them (which also recomputes MeshLab's normals) and compact the vertex
# vector. The saved file must still hold, for every remaining vertex, the RF that belongs to it:
# for a Lambertian material that is a known constant of the vertex's normal, checked in Python.
source "$(dirname "$0")/lib.sh"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_radiance_ply.py"

"$MAKE_SCENE" sphere --level 3 -o "$WORK/sphere.ply"
# Our create filter (PB degree 3, Lambertian), then MeshLab's own filters.
create_radiance_mlx "$WORK/edit.mlx" 0 3 false 0 0 0.5 1 1 \
    --filter "Conditional Vertex Selection" "condSelect=(x > 0.1)" --filter "Delete Selected Vertices" \
    --filter "Compact vertices" --filter "Compact faces"
run_meshlabserver "$WORK/edit.log" -i "$WORK/sphere.ply" -o "$WORK/edited.rply" -m vc vn -s "$WORK/edit.mlx" \
    || { cat "$WORK/edit.log" >&2; fail "create + delete + compact + save failed"; }
grep -q "Deleted [1-9][0-9]* vertices" "$WORK/edit.log" || { cat "$WORK/edit.log" >&2; fail "MeshLab deleted nothing: the test would prove nothing"; }
python3 "$PLY_READER" "$WORK/sphere.ply" --summary >"$WORK/before.json"
python3 "$PLY_READER" "$WORK/edited.rply" --summary >"$WORK/after.json"
python3 - "$WORK/before.json" "$WORK/after.json" <<'PY' || fail "vertex count did not shrink"
import json, sys
def count(path):
    return json.load(open(path))["vertex_count"]
before, after = count(sys.argv[1]), count(sys.argv[2])
print(f"vertices: {before} -> {after}")
sys.exit(0 if 0 < after < before else 1)
PY
$CHECK lambert_sphere "$WORK/edited.rply" PB 3 0.5 1 1 3 0.05 230 60 40 || fail "radiance rows no longer match their vertices"
note "ok"
