#!/usr/bin/env bash
# Normal-map baking, ours ("Bake Normal Map") against MeshLab's own "Transfer: Vertex Attributes to
# Texture (1 or 2 meshes)", both through Debian's meshlabserver, on the same inputs and into the
# same texture layout (MeshLab's "Parametrization: Trivial Per-Triangle" of the simplified mesh):
#   quality: bunny00 (a real scan, 75,408 faces) simplified by MeshLab to 2 % (1,508 faces), 4096^2;
#   speed:   armadillo subdivided 3 times by MeshLab (3,328,000 faces, 1,664,002 vertices),
#            simplified to 2 % (66,560 faces), 4096^2.
# Error: tools/normal_map_error (every scan vertex -> nearest point of the simplified mesh -> map,
# angle to the scan's vertex normal; a correspondence neither baker uses). MeshLab's 8-bit codes
# are truncated, so its map is also scored decoded at code + 0.5 (its best case).
# Time: our filter's own figure from the log, and for both filters the wall time of
# (load + filter) - (load only) of whole meshlabserver runs.
# Usage: bench/bake_vs_meshlab.sh [OUTDIR] [quality|speed|all]   (default out/bake-bench all)
# Needs the build (build/meshlab-prefix, build/tools/normal_map_error) and data-cache/meshes.
set -euo pipefail
REPO="$(cd "$(dirname "$0")/.." && pwd)"
OUT="${1:-$REPO/out/bake-bench}"; WHICH="${2:-all}"
mkdir -p "$OUT"; OUT="$(cd "$OUT" && pwd)"
export XDG_CONFIG_HOME="$OUT/config"; mkdir -p "$XDG_CONFIG_HOME"
SERVER="$REPO/build/meshlab-prefix/bin/meshlabserver"
export MESHLABSERVER="$SERVER"
ERROR_TOOL="$REPO/build/tools/normal_map_error"
TRANSFER="bash $REPO/bench/meshlab_transfer.sh"
server() { local log="$1"; shift; timeout 3600 xvfb-run -a -s "-screen 0 1280x1024x24" "$SERVER" "$@" >"$log" 2>&1; }
now() { date +%s.%N; }

# bbox diagonal / 50 of a PLY/OFF read by MeshLab's log? Simpler: from the OFF file itself.
diag50() {
    python3 - "$1" <<'PY'
import sys
lines = [l for l in open(sys.argv[1]) if l.strip() and not l.startswith("#")]
head = lines[0].split()
counts = lines[1].split() if len(head) == 1 else head[1:]
n = int(counts[0]); pts = [list(map(float, l.split()[:3])) for l in lines[(2 if len(head) == 1 else 1):][:n]]
lo = [min(p[k] for p in pts) for k in range(3)]; hi = [max(p[k] for p in pts) for k in range(3)]
print("%.6g" % (sum((h - l) ** 2 for h, l in zip(hi, lo)) ** 0.5 / 50))
PY
}

# ours CASE_DIR SIZE BITS(0=16,1=8) NAME: bakes with our filter into the case's own layout.
ours() {
    local dir="$1" size="$2" bits="$3" name="$4"
    cat >"$dir/$name.mlx" <<MLX
<!DOCTYPE FilterScript>
<FilterScript>
$(bash "$REPO/scripts/bake_normal_map_filter.sh" 0 "$size" 0 "$bits" false false "$dir/$name/baked_normal.png")
</FilterScript>
MLX
    mkdir -p "$dir/$name"
    local t0 t1 t2
    t0=$(now); server "$dir/$name.load.log" -i "$dir/source.ply" -i "$dir/target.ply" || { cat "$dir/$name.load.log"; exit 1; }
    t1=$(now); server "$dir/$name.log" -i "$dir/source.ply" -i "$dir/target.ply" -s "$dir/$name.mlx" \
        || { cat "$dir/$name.log"; exit 1; }
    t2=$(now)
    local line; line=$(grep -m1 -o "LOG: 2 Bake Normal Map: object space.*" "$dir/$name.log")
    echo "ours ($name): $line"
    python3 -c "print('ours (%s): filter wall time %.2f s (load only %.2f s)' % ('$name', ($t2 - $t1) - ($t1 - $t0), $t1 - $t0))"
}

score() {  # score CASE_DIR MAP LABEL [extra args]
    local dir="$1" map="$2" label="$3"; shift 3
    echo "error of $label:"
    "$ERROR_TOOL" "$dir/source.ply" "$dir/target.obj" "$map" "$@" | sed 's/^/    /'
}

run_case() {  # run_case NAME SCAN FACES SIZE UPPERBOUND REPEATS
    local name="$1" scan="$2" faces="$3" size="$4" bound="$5" repeats="$6"
    local dir="$OUT/$name"
    echo "== $name: $(basename "$scan") -> $faces faces, ${size}^2 =="
    $TRANSFER prepare "$scan" "$dir" "$faces" "$size" >/dev/null
    ours "$dir" "$size" 0 ours16
    ours "$dir" "$size" 1 ours8
    $TRANSFER run "$dir/source.ply" "$dir/target.ply" "$size" "$bound" "$dir/meshlab.png" "$repeats" | sed 's/^/meshlab: /'
    score "$dir" "$dir/ours16/baked_normal.png" "ours, 16 bit"
    score "$dir" "$dir/ours8/baked_normal.png" "ours, 8 bit"
    score "$dir" "$dir/meshlab.png" "MeshLab, 8 bit"
    score "$dir" "$dir/meshlab.png" "MeshLab, 8 bit decoded at code + 0.5" --code-offset 0.5
}

MESHES="$REPO/data-cache/meshes"
if [ "$WHICH" = quality ] || [ "$WHICH" = all ]; then
    run_case bunny_2pct "$MESHES/bunny00.off" 1508 4096 "$(diag50 "$MESHES/bunny00.off")" 1
fi
if [ "$WHICH" = speed ] || [ "$WHICH" = all ]; then
    mkdir -p "$OUT/armadillo_s3"
    RADIANCE_BUILD_DIR="$REPO/build" bash "$REPO/scripts/filter_script.sh" --out "$OUT/armadillo_s3/subdivide.mlx" \
        --filter "Subdivision Surfaces: Midpoint" Iterations=3 Threshold=0 Selected=false
    server "$OUT/armadillo_s3/subdivide.log" -i "$MESHES/armadillo.off" -s "$OUT/armadillo_s3/subdivide.mlx" \
        -o "$OUT/armadillo_s3/scan.ply" || { cat "$OUT/armadillo_s3/subdivide.log"; exit 1; }
    run_case armadillo_s3_2pct "$OUT/armadillo_s3/scan.ply" 66560 4096 "$(diag50 "$MESHES/armadillo.off")" 1
fi
