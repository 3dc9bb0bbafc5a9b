#!/usr/bin/env bash
# Extra per-vertex blocks that no plugin interprets survive open + save through the real meshlabserver:
#   1. a file with a block 'curvature' (and a 'prt' block that is not a valid transfer field) is saved
#      back byte for byte;
#   2. after MeshLab's own delete + compact, each remaining vertex keeps its own block values;
#   3. after a filter that adds vertices (midpoint subdivision) the block cannot be saved: the save
#      goes on without it and says so on stderr (nothing is dropped silently);
#   4. a foreign vertex property the format does not know is reported as not loaded;
#   5. our geometry-only simplification carries the blocks: each remaining vertex keeps its values;
#   6. our PRT subdivision, which creates vertices, removes them and says so.
# The input files are written here with struct (independent of the code under test), in the exact
# layout of our writer (docs/radiance-ply-format.md).
source "$(dirname "$0")/lib.sh"

python3 - "$WORK" <<'PY'
import struct, sys
work = sys.argv[1]
n_side = 6
pos = [(i / 5.0, j / 5.0, 0.0) for j in range(n_side) for i in range(n_side)]
faces = []
for j in range(n_side - 1):
    for i in range(n_side - 1):
        a = j * n_side + i
        faces += [(a, a + 1, a + n_side), (a + 1, a + n_side + 1, a + n_side)]
def write(path, foreign=False):
    head = ["ply", "format binary_little_endian 1.0", "comment radiance_format_version 1",
            "comment block prt width 3", "comment block_meta prt kind made_up",
            "comment block curvature width 2", "comment block_meta curvature note two  spaces",
            "comment block_meta curvature unit 1/m",
            f"element vertex {len(pos)}"]
    head += [f"property float {p}" for p in ("x", "y", "z", "nx", "ny", "nz")]
    if foreign:
        head.append("property float confidence")
    head += [f"property float prt_{i}" for i in range(3)] + ["property float curvature_0", "property float curvature_1"]
    head += [f"element face {len(faces)}", "property list uchar int vertex_indices", "end_header"]
    body = bytearray()
    for v, (x, y, z) in enumerate(pos):
        body += struct.pack("<6f", x, y, z, 0.0, 0.0, 1.0)
        if foreign:
            body += struct.pack("<f", 0.5)
        # Block values are functions of the position, so that a test can tell which vertex owns them.
        body += struct.pack("<3f", -v, 0.25, float("nan"))
        body += struct.pack("<2f", 10 * x + y, 100.0 + v)
    for f in faces:
        body += struct.pack("<B3i", 3, *f)
    open(path, "wb").write(("\n".join(head) + "\n").encode() + bytes(body))
write(f"{work}/in.rply")
write(f"{work}/foreign.rply", foreign=True)
PY

# 1. Open + save: the same bytes.
run_meshlabserver "$WORK/save.log" -i "$WORK/in.rply" -o "$WORK/out.rply" -m vn \
    || { cat "$WORK/save.log" >&2; fail "open + save failed"; }
cmp "$WORK/in.rply" "$WORK/out.rply" || { cat "$WORK/save.log" >&2; fail "the saved file differs from the opened one"; }
grep -q "The block is kept as it is and saved again unchanged" "$WORK/save.log" \
    || { cat "$WORK/save.log" >&2; fail "no warning about the 'prt' block that is not a transfer field"; }
note "open + save keeps both blocks byte for byte"

# 2. MeshLab's delete + compact: the rows follow their vertices.
bash "$RADIANCE_SOURCE_DIR/scripts/filter_script.sh" --out "$WORK/delete.mlx" \
    --filter "Conditional Vertex Selection" "condSelect=(x > 0.5)" --filter "Delete Selected Vertices" \
    --filter "Compact vertices" --filter "Compact faces"
run_meshlabserver "$WORK/delete.log" -i "$WORK/in.rply" -o "$WORK/deleted.rply" -m vn -s "$WORK/delete.mlx" \
    || { cat "$WORK/delete.log" >&2; fail "delete + compact + save failed"; }
python3 - "$PLY_READER" "$WORK/deleted.rply" <<'PY' || fail "block rows do not follow their vertices"
import importlib.util, math, sys
spec = importlib.util.spec_from_file_location("ply_reader", sys.argv[1])
reader = importlib.util.module_from_spec(spec); spec.loader.exec_module(reader)
ply = reader.read_ply(sys.argv[2])
v = ply.data["vertex"]
n = len(v["x"])
assert 0 < n < 36, n
assert all(x <= 0.5 for x in v["x"])
for i in range(n):
    x, y = v["x"][i], v["y"][i]
    original = round(x * 5) + 6 * round(y * 5)  # the vertex's index in the input grid
    assert abs(v["curvature_0"][i] - (10 * x + y)) < 1e-5, i
    assert v["curvature_1"][i] == 100.0 + original, (i, v["curvature_1"][i], original)
    assert v["prt_0"][i] == -original and v["prt_1"][i] == 0.25 and math.isnan(v["prt_2"][i])
assert "block_meta curvature unit 1/m" in ply.comments and "block_meta curvature note two  spaces" in ply.comments
print(f"{n} of 36 vertices kept, each with its own block values")
PY
note "delete + compact: block values follow their vertices"

# 3. A filter that adds vertices: saved without the blocks, and the log says so.
filter_script "$WORK/subdivide.mlx" "Subdivision Surfaces: Midpoint" Iterations=1 Threshold=0 Selected=false
run_meshlabserver "$WORK/subdivide.log" -i "$WORK/in.rply" -o "$WORK/subdivided.rply" -m vn -s "$WORK/subdivide.mlx" \
    || { cat "$WORK/subdivide.log" >&2; fail "subdivide + save failed"; }
grep -q "the extra vertex blocks 'prt', 'curvature' of the opened file cannot be saved: [0-9]* of [0-9]* vertices were created" \
    "$WORK/subdivide.log" || { cat "$WORK/subdivide.log" >&2; fail "no warning about the blocks left out"; }
# (Read whole before grepping: grep -q closes the pipe at the first match, which under pipefail
# fails the reader with a broken pipe.)
summary="$(python3 "$PLY_READER" "$WORK/subdivided.rply" --summary)" || fail "no file written"
grep -q '"vertex_count": [0-9]' <<<"$summary" || fail "no file written"
if grep -q "curvature" "$WORK/subdivided.rply"; then fail "the subdivided file claims a block its new vertices have no values for"; fi
note "subdivision: saved without the blocks, with a warning"

# 4. A foreign property: loaded without it, and stderr says so.
run_meshlabserver "$WORK/foreign.log" -i "$WORK/foreign.rply" -o "$WORK/foreign_out.rply" -m vn \
    || { cat "$WORK/foreign.log" >&2; fail "open + save of the foreign file failed"; }
grep -q "vertex property 'confidence' of the file is not part of the radiance PLY format and was not loaded" \
    "$WORK/foreign.log" || { cat "$WORK/foreign.log" >&2; fail "the skipped property was not reported"; }
cmp -s "$WORK/foreign_out.rply" "$WORK/out.rply" || fail "the foreign file did not save as the same mesh without 'confidence'"
note "foreign property reported"

# 5. Simplification (geometry metric: the mesh has no radiance): the blocks follow their vertices.
bash "$RADIANCE_SOURCE_DIR/scripts/write_simplify_mlx.sh" "$WORK/simplify.mlx" 0.5 3
run_meshlabserver "$WORK/simplify.log" -i "$WORK/in.rply" -o "$WORK/simplified.rply" -m vn -s "$WORK/simplify.mlx" \
    || { cat "$WORK/simplify.log" >&2; fail "simplify + save failed"; }
python3 - "$PLY_READER" "$WORK/simplified.rply" <<'PY' || fail "block rows do not follow their vertices through the simplification"
import importlib.util, math, sys
spec = importlib.util.spec_from_file_location("ply_reader", sys.argv[1])
reader = importlib.util.module_from_spec(spec); spec.loader.exec_module(reader)
ply = reader.read_ply(sys.argv[2])
v = ply.data["vertex"]
n = len(v["x"])
assert 0 < n < 36 and 0 < len(ply.data["face"]["vertex_indices"]) <= 25, (n, len(ply.data["face"]["vertex_indices"]))
for i in range(n):
    x, y = v["x"][i], v["y"][i]
    original = round(x * 5) + 6 * round(y * 5)  # half-edge collapses keep original positions
    assert abs(x * 5 - round(x * 5)) < 1e-5 and abs(y * 5 - round(y * 5)) < 1e-5, (x, y)
    assert v["curvature_1"][i] == 100.0 + original and v["prt_0"][i] == -original, i
print(f"simplified to {n} vertices, each with its own block values")
PY
note "simplification: block values follow their vertices"

# 6. PRT transfer, then a uniform PRT subdivision (new vertices): the blocks are removed, with a warning.
bash "$RADIANCE_SOURCE_DIR/scripts/write_prt_mlx.sh" "$WORK/prt.mlx" transfer:2:16 uniform:4
run_meshlabserver "$WORK/prt.log" -i "$WORK/in.rply" -o "$WORK/prt.rply" -m vn -s "$WORK/prt.mlx" \
    || { cat "$WORK/prt.log" >&2; fail "transfer + subdivision + save failed"; }
grep -q "Uniform PRT subdivision .*: 50 -> 200 faces" "$WORK/prt.log" || { cat "$WORK/prt.log" >&2; fail "no subdivision happened"; }
grep -q "The extra vertex blocks 'prt', 'curvature' of the opened file were removed: the subdivision rebuilds the mesh" \
    "$WORK/prt.log" || { cat "$WORK/prt.log" >&2; fail "no warning about the block the subdivision removed"; }
if grep -aq "curvature" "$WORK/prt.rply"; then fail "the subdivided file claims the block"; fi
note "ok"
