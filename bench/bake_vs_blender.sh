#!/usr/bin/env bash
# Normal baking, ours ("Bake Normal Map" through meshlabserver) against Blender's Cycles "Selected to
# Active" bake (Debian's Blender 3.4, CPU, headless), on the same high / low pairs with the same UVs:
# a unit sphere (327,680 faces onto 960) and a torus (1,048,576 faces onto 2,304) made by
# bench/blender/make_bake_pairs.py, and a real scan (the armadillo, two Catmull-Clark levels, onto
# itself decimated to ~3,000 faces with Smart UV Project UVs: bench/blender/make_scan_pair.py).
# Both tangent space (MikkTSpace) and object space, 16-bit PNG for ours (LEAN off: Blender has none),
# a float image for Blender's. Ray search: ours +/- D along the normal (maximum distance D), Blender's
# cage extrusion D with maximum ray distance 2 D (the same segment); D = 0.05 for the analytic shapes,
# for the scan twice the largest low-to-high distance (scan_distance.txt).
# Error (bench/blender/evaluate_bake.py): every texel centre inside a UV triangle; the truth is the
# analytic normal where the texel's ray meets the exact sphere / torus, and for the scan the high
# mesh's interpolated normal where the ray meets it, found by Blender's mathutils BVH tree
# (bench/blender/scan_reference.py, every 4th row and column at 2048^2, every 8th at 4096^2): at the
# nearer hit along +/- the normal (our rule; rows "blender", "ours") and at the first hit from the
# cage inwards (Cycles' rule; rows ".../cage-rule"), plus the two bakers' agreement with each other. Time: the bake alone (Blender: bpy.ops.object.bake; ours:
# the filter's own "in X s", which includes filling the gutters and writing the PNG), its processor
# time (all threads; with other programs on the cores it varies far less than the wall time) and
# each program's wall time.
# Then the render comparison (bench/blender/render_compare.py): Cycles renders of the high mesh and of
# the low mesh with our .glb (imported by Blender's glTF add-on), our 16-bit map, Blender's map (float
# and rounded to 8 bits), image error of each low render against the high one.
# Outside CI (about half an hour at 2048^2 and 4096^2 on 2 cores).
# Usage: bench/bake_vs_blender.sh [SIZE ...]     (default: 2048 4096)
# Environment: BUILD_DIR (default <repo>/build), BLENDER (default: blender on PATH), PYTHON with
#              numpy (default $BUILD_DIR/python-venv/bin/python), D (default 0.05), SCAN (default
#              data-cache/meshes/armadillo.off), SHAPES (default "sphere torus scan"), SPACES (default
#              "tangent object"), RENDER (default 1: the render comparison; 0: skip), RENDER_SIZE
#              (default 256 pixels), RENDER_SAMPLES (default 16)
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
BLENDER="${BLENDER:-$(command -v blender || true)}"
PYTHON="${PYTHON:-$BUILD_DIR/python-venv/bin/python}"
D="${D:-0.05}"
SCAN="${SCAN:-$REPO/data-cache/meshes/armadillo.off}"
read -r -a SHAPE_LIST <<< "${SHAPES:-sphere torus scan}"
read -r -a SPACE_LIST <<< "${SPACES:-tangent object}"
SIZES=("$@")
[ ${#SIZES[@]} -gt 0 ] || SIZES=(2048 4096)
[ -n "$BLENDER" ] || { echo "Blender not found: apt-get install blender, or set BLENDER" >&2; exit 1; }
SERVER="$BUILD_DIR/meshlab-prefix/bin/meshlabserver"
[ -x "$SERVER" ] || { echo "no $SERVER: build the project first (scripts/setup.sh)" >&2; exit 1; }
WORK="$BUILD_DIR/bench-work/bake_vs_blender"
mkdir -p "$WORK"
export XDG_CONFIG_HOME="$WORK/config" HOME="$WORK"
blender_run() {  # LOG BLEND SCRIPT ARGS...
  local log="$1" blend="$2" script="$3"
  shift 3
  local file=()
  [ -z "$blend" ] || file=("$blend")
  "$BLENDER" -b "${file[@]}" --factory-startup -noaudio --python-exit-code 1 -P "$script" -- "$@" > "$log" 2>&1 \
    || { tail -20 "$log" >&2; exit 1; }
}

if [ ! -s "$WORK/pairs.blend" ]; then
  blender_run "$WORK/pairs.log" "" "$REPO/bench/blender/make_bake_pairs.py" "$WORK"
  grep "^pair" "$WORK/pairs.log"
fi
if [[ " ${SHAPE_LIST[*]} " == *" scan "* ]] && [ ! -s "$WORK/scan_low.corners" ]; then
  [ -s "$SCAN" ] || { echo "no scan $SCAN: set SCAN to an OFF mesh (scripts/fetch_data.sh fetches armadillo.off)" >&2; exit 1; }
  blender_run "$WORK/scan_pair.log" "$WORK/pairs.blend" "$REPO/bench/blender/make_scan_pair.py" "$WORK" "$SCAN"
  grep "^pair" "$WORK/scan_pair.log"
fi

now() { date +%s.%N; }
stats() { read -r _ texels _ mean _ median _ p95 _ max; }
row() { printf '%-6s %5s %-7s %-8s %9s %9s %9s %8s %10s %10s %10s\n' "$@"; }
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores"
row shape size space baker "mean deg" median p95 max "bake s" "cpu s" "wall s"
for size in "${SIZES[@]}"; do
  for shape in "${SHAPE_LIST[@]}"; do
    distance="$D"
    truth="$shape"
    if [ "$shape" = scan ]; then
      distance=$(cat "$WORK/scan_distance.txt")
      stride=$(( size / 512 > 1 ? size / 512 : 1 ))
      ref="$WORK/scan_reference_${size}.npz"
      if [ ! -s "$ref" ]; then
        blender_run "$WORK/scan_reference_${size}.log" "$WORK/pairs.blend" "$REPO/bench/blender/scan_reference.py" \
          scan "$size" "$stride" "$distance" "$ref"
      fi
      truth="reference:$ref"
    fi
    for space in "${SPACE_LIST[@]}"; do
      # Blender, Cycles on the CPU.
      out="$WORK/blender_${shape}_${size}_${space}.npy"
      t0=$(now)
      blender_run "$WORK/blender_${shape}_${size}_${space}.log" "$WORK/pairs.blend" "$REPO/bench/blender/cycles_bake.py" \
        "$shape" "$size" "$distance" "$out" "$space"
      wall=$(awk -v a="$(now)" -v b="$t0" 'BEGIN {printf "%.2f", a - b}')
      bake=$(awk '/^BLENDER_BAKE_SECONDS/ {printf "%.2f", $2}' "$WORK/blender_${shape}_${size}_${space}.log")
      cpu=$(awk '/^BLENDER_BAKE_CPU_SECONDS/ {printf "%.2f", $2}' "$WORK/blender_${shape}_${size}_${space}.log")
      stats < <("$PYTHON" "$REPO/bench/blender/evaluate_bake.py" "$truth" "$space" "$WORK/${shape}_low.corners" "$out")
      row "$shape" "$size" "$space" blender "$mean" "$median" "$p95" "$max" "$bake" "$cpu" "$wall"

      # Ours, 16 bit, LEAN off, through meshlabserver.
      base="$WORK/ours_${shape}_${size}_${space}"
      spaceIndex=$([ "$space" = tangent ] && echo 1 || echo 0)
      { echo '<!DOCTYPE FilterScript>'; echo '<FilterScript>'
        bash "$REPO/scripts/bake_normal_map_filter.sh" 0 "$size" "$spaceIndex" 0 false false "${base}_normal.png" 0 false \
          maxDistance="$distance" lean=false
        echo '</FilterScript>'; } > "$base.mlx"
      t0=$(now)
      xvfb-run -a -s "-screen 0 640x480x24" "$SERVER" -i "$WORK/${shape}_high.ply" -i "$WORK/${shape}_low.ply" \
        -s "$base.mlx" > "$base.log" 2>&1 || { tail -20 "$base.log" >&2; exit 1; }
      wall=$(awk -v a="$(now)" -v b="$t0" 'BEGIN {printf "%.2f", a - b}')
      grep -q "per-vertex texture coordinates" "$base.log" || { echo "our bake did not use the low mesh's UVs" >&2; exit 1; }
      bake=$(grep -o "faces) in [0-9.]* s" "$base.log" | head -1 | awk '{print $3}')
      cpu=$(grep -o "processor time [0-9.]* s" "$base.log" | head -1 | awk '{print $3}')
      stats < <("$PYTHON" "$REPO/bench/blender/evaluate_bake.py" "$truth" "$space" "$WORK/${shape}_low.corners" "${base}_normal.png")
      row "$shape" "$size" "$space" ours "$mean" "$median" "$p95" "$max" "$bake" "$cpu" "$wall"
      grep -o "(bake [^)]*)" "$base.log" | head -1 | sed 's/^/                 ours: /' >&2
      if [ "$shape" = scan ]; then
        # The same two maps against the cage rule's reference, and against each other.
        for baker in blender ours; do
          map="$out"
          [ $baker = ours ] && map="${base}_normal.png"
          stats < <("$PYTHON" "$REPO/bench/blender/evaluate_bake.py" "reference-cage:$ref" "$space" "$WORK/${shape}_low.corners" "$map")
          row "$shape" "$size" "$space" "$baker/cage-rule" "$mean" "$median" "$p95" "$max" - - -
        done
        stats < <("$PYTHON" "$REPO/bench/blender/evaluate_bake.py" agree "$space" "$WORK/${shape}_low.corners" "${base}_normal.png" "$out")
        row "$shape" "$size" "$space" "ours-vs-blender" "$mean" "$median" "$p95" "$max" - - -
      fi
    done
  done
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "(texels evaluated: every texel centre inside a UV triangle of the low mesh, the scan's at the reference's texels; D = $D, scan D = $(cat "$WORK/scan_distance.txt" 2>/dev/null || echo -))"

[ "${RENDER:-1}" = 1 ] || exit 0
[[ " ${SPACE_LIST[*]} " == *" tangent "* ]] || exit 0
# Render comparison: the tangent-space maps of the first size; our .glb from one more (untimed) bake.
size="${SIZES[0]}"
echo
echo "render comparison: Cycles CPU, ${RENDER_SIZE:-256}^2 pixels, ${RENDER_SAMPLES:-16} samples, maps of ${size}^2; error of each low render against the high mesh's, linear RGB"
printf '%-6s %-14s %9s %10s %10s %10s %10s\n' shape map pixels rmse "mean abs" "rmse all" "mean all"
for shape in "${SHAPE_LIST[@]}"; do
  distance="$D"
  [ "$shape" = scan ] && distance=$(cat "$WORK/scan_distance.txt")
  base="$WORK/gltf_${shape}_${size}"
  { echo '<!DOCTYPE FilterScript>'; echo '<FilterScript>'
    bash "$REPO/scripts/bake_normal_map_filter.sh" 0 "$size" 1 0 false false "${base}_normal.png" 0 true \
      maxDistance="$distance" lean=false
    echo '</FilterScript>'; } > "$base.mlx"
  xvfb-run -a -s "-screen 0 640x480x24" "$SERVER" -i "$WORK/${shape}_high.ply" -i "$WORK/${shape}_low.ply" \
    -s "$base.mlx" > "$base.log" 2>&1 || { tail -20 "$base.log" >&2; exit 1; }
  [ -s "$base.glb" ] || { echo "no $base.glb" >&2; exit 1; }
  blender_run "$WORK/render_${shape}.log" "$WORK/pairs.blend" "$REPO/bench/blender/render_compare.py" \
    "$shape" "$WORK/renders" "$base.glb" "${base}_normal.png" "$WORK/blender_${shape}_${size}_tangent.npy" \
    "${RENDER_SIZE:-256}" "${RENDER_SAMPLES:-16}"
  awk '/^RENDER/ {printf "%-6s %-14s %9d %10.6f %10.6f %10.6f %10.6f\n", $2, $3, $5, $7, $9, $11, $13}' "$WORK/render_${shape}.log"
done
