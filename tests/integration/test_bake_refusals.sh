#!/usr/bin/env bash
# "Bake Normal Map" on bad input, through the real meshlabserver: a clear message in the log, no
# crash, no file written, and the target layer saved unchanged:
#  - a target without faces; - the source equal to the target; - overlapping texture coordinates;
#  - a texture size that is not a power of two; - an absurdly large texture size.
source "$(dirname "$0")/lib.sh"
source "$(dirname "$0")/bake_mlx.sh"

"$MAKE_SCENE" sphere --level 4 -o "$WORK/fine.ply"
"$MAKE_SCENE" sphere --level 1 -o "$WORK/coarse.ply"
python3 - "$WORK" <<'PY'
import sys
work = sys.argv[1]
# A point cloud (no faces).
with open(f"{work}/points.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n")
# Two triangles whose UV triangles overlap (wedge coordinates as a PLY face property: Debian's
# meshlabserver 2020.09 aborts on loading any OBJ).
with open(f"{work}/overlap.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 2\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n"
            "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
            "3 0 1 2 6 0.1 0.1 0.9 0.1 0.1 0.9\n3 0 3 1 6 0.2 0.2 0.8 0.2 0.2 0.8\n")
PY

# expect_bake_refusal NAME MESSAGE TARGET MLX: the target is loaded after the scan (layer 1, current).
expect_bake_refusal() {
    local name="$1" message="$2" target="$3" mlx="$4"
    local ext="${target##*.}"
    mkdir -p "$WORK/$name"
    run_meshlabserver "$WORK/$name.ref.log" -i "$WORK/fine.ply" -i "$target" -o "$WORK/$name/ref.$ext" -m wt vn \
        || fail "$name: cannot save the reference"
    run_meshlabserver "$WORK/$name.log" -i "$WORK/fine.ply" -i "$target" -s "$mlx" -o "$WORK/$name/out.$ext" -m wt vn || true
    grep -qF "$message" "$WORK/$name.log" || { cat "$WORK/$name.log" >&2; fail "$name: no message '$message'"; }
    grep -qF "The layers are unchanged" "$WORK/$name.log" || fail "$name: the message does not say the layers are unchanged"
    if [ -e "$WORK/$name/out.$ext" ]; then
        cmp -s "$WORK/$name/ref.$ext" "$WORK/$name/out.$ext" || fail "$name: layer changed by a refused filter"
    fi
    if ls "$WORK/$name/"*_normal.png "$WORK/$name/"*.part >/dev/null 2>&1; then fail "$name: files written"; fi
    note "$name refused: $(grep -F "$message" "$WORK/$name.log" | head -n 1)"
}

bake_mlx "$WORK/ok.mlx" 0 64 0 0 false "$WORK/REPLACE/baked_normal.png"
sed "s#REPLACE#points#" "$WORK/ok.mlx" >"$WORK/points.mlx"
expect_bake_refusal points "has no faces" "$WORK/points.ply" "$WORK/points.mlx"
bake_mlx "$WORK/same.mlx" 1 64 0 0 false "$WORK/same/baked_normal.png"
expect_bake_refusal same "are the same" "$WORK/coarse.ply" "$WORK/same.mlx"
sed "s#REPLACE#overlap#" "$WORK/ok.mlx" >"$WORK/overlap.mlx"
expect_bake_refusal overlap "lie inside two or more faces (overlapping charts)" "$WORK/overlap.ply" "$WORK/overlap.mlx"
bake_mlx "$WORK/npot.mlx" 0 1000 0 0 false "$WORK/npot/baked_normal.png"
expect_bake_refusal npot "Texture size 1000 is not a power of two" "$WORK/coarse.ply" "$WORK/npot.mlx"
bake_mlx "$WORK/huge.mlx" 0 65536 0 0 false "$WORK/huge/baked_normal.png"
expect_bake_refusal huge "16384" "$WORK/coarse.ply" "$WORK/huge.mlx"
note "refusals ok"
