#!/usr/bin/env bash
# Tangent-space normal baking, ours ("Bake Normal Map", MikkTSpace, through meshlabserver) against
# Blender's Cycles "Selected to Active" bake (Debian's Blender 3.4, CPU, headless), on the same
# high / low pairs with the same UVs (bench/blender/make_bake_pairs.py): a unit sphere (327,680 faces
# onto 960) and a torus (1,048,576 faces onto 2,304). Ray search: ours +/- D along the normal
# (maximum distance D), Blender's cage extrusion D with maximum ray distance 2 D (the same segment).
# Error: bench/blender/evaluate_bake.py, angle between the map decoded the MikkTSpace way and the
# exact surface normal where the texel's ray meets the analytic surface. Time: the bake alone
# (Blender: bpy.ops.object.bake; ours: the filter's own "in X s", which includes filling the gutters
# and writing the PNG) and each program's wall time. Outside CI (minutes at 4096^2).
# Usage: bench/bake_vs_blender.sh [SIZE ...]     (default: 2048 4096)
# Environment: BUILD_DIR (default <repo>/build), BLENDER (default: blender on PATH), PYTHON with
#              numpy (default $BUILD_DIR/python-venv/bin/python), D (default 0.05)
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
BLENDER="${BLENDER:-$(command -v blender || true)}"
PYTHON="${PYTHON:-$BUILD_DIR/python-venv/bin/python}"
D="${D:-0.05}"
SIZES=("$@")
[ ${#SIZES[@]} -gt 0 ] || SIZES=(2048 4096)
[ -n "$BLENDER" ] || { echo "Blender not found: apt-get install blender, or set BLENDER" >&2; exit 1; }
SERVER="$BUILD_DIR/meshlab-prefix/bin/meshlabserver"
[ -x "$SERVER" ] || { echo "no $SERVER: build the project first (scripts/setup.sh)" >&2; exit 1; }
WORK="$BUILD_DIR/bench-work/bake_vs_blender"
mkdir -p "$WORK"
export XDG_CONFIG_HOME="$WORK/config" HOME="$WORK"

if [ ! -s "$WORK/pairs.blend" ]; then
  "$BLENDER" -b --factory-startup -noaudio --python-exit-code 1 -P "$REPO/bench/blender/make_bake_pairs.py" -- "$WORK" \
    > "$WORK/pairs.log" 2>&1 || { cat "$WORK/pairs.log" >&2; exit 1; }
  grep "^pair" "$WORK/pairs.log"
fi

now() { date +%s.%N; }
printf '%-7s %5s  %-8s %9s %9s %9s %8s %10s %10s\n' shape size baker "mean deg" "median" "p95" "max" "bake s" "wall s"
for size in "${SIZES[@]}"; do
  for shape in sphere torus; do
    # Blender, Cycles on the CPU.
    out="$WORK/blender_${shape}_${size}.npy"
    t0=$(now)
    "$BLENDER" -b "$WORK/pairs.blend" -noaudio --python-exit-code 1 -P "$REPO/bench/blender/cycles_bake.py" -- \
      "$shape" "$size" "$D" "$out" > "$WORK/blender_${shape}_${size}.log" 2>&1 \
      || { tail -20 "$WORK/blender_${shape}_${size}.log" >&2; exit 1; }
    wall=$(awk -v a="$(now)" -v b="$t0" 'BEGIN {print a - b}')
    bake=$(awk '/^BLENDER_BAKE_SECONDS/ {print $2}' "$WORK/blender_${shape}_${size}.log")
    read -r _ texels _ mean _ median _ p95 _ max < <("$PYTHON" "$REPO/bench/blender/evaluate_bake.py" "$shape" "$WORK/${shape}_low.corners" "$out")
    printf '%-7s %5s  %-8s %9s %9s %9s %8s %10.2f %10.2f\n' "$shape" "$size" blender "$mean" "$median" "$p95" "$max" "$bake" "$wall"

    # Ours, MikkTSpace tangent space, 16 bit, through meshlabserver.
    base="$WORK/ours_${shape}_${size}"
    { echo '<!DOCTYPE FilterScript>'; echo '<FilterScript>'
      bash "$REPO/scripts/bake_normal_map_filter.sh" 0 "$size" 1 0 false false "${base}_normal.png" 0 \
        | sed "s|name=\"maxDistance\" value=\"0\"|name=\"maxDistance\" value=\"$D\"|"
      echo '</FilterScript>'; } > "$base.mlx"
    t0=$(now)
    xvfb-run -a -s "-screen 0 640x480x24" "$SERVER" -i "$WORK/${shape}_high.ply" -i "$WORK/${shape}_low.ply" \
      -s "$base.mlx" > "$base.log" 2>&1 || { tail -20 "$base.log" >&2; exit 1; }
    wall=$(awk -v a="$(now)" -v b="$t0" 'BEGIN {print a - b}')
    grep -q "per-vertex texture coordinates" "$base.log" || { echo "our bake did not use the low mesh's UVs" >&2; exit 1; }
    bake=$(grep -o "faces) in [0-9.]* s" "$base.log" | head -1 | awk '{print $3}')
    read -r _ texels _ mean _ median _ p95 _ max < <("$PYTHON" "$REPO/bench/blender/evaluate_bake.py" "$shape" "$WORK/${shape}_low.corners" "${base}_normal.png")
    printf '%-7s %5s  %-8s %9s %9s %9s %8s %10.2f %10.2f\n' "$shape" "$size" ours "$mean" "$median" "$p95" "$max" "$bake" "$wall"
  done
done
echo "(texels evaluated per case: every texel centre inside a UV triangle of the low mesh; D = $D)"
