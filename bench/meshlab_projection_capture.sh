#!/usr/bin/env bash
# MeshLab's own "Project active rasters color to current mesh" on the TRAINING rasters of a capture
# (every K-th raster of project.mlp left out, 1-based, as bench_fit_capture --held-out-every K and the
# filter's heldOutEvery), through meshlabserver, timed; the vertex colours it writes are what
# bench_fit_capture --meshlab-colors scores on the held-out photographs.
#   bench/meshlab_projection_capture.sh CAPTURE [K] [OUT_DIR] [DEPTH]
#     CAPTURE: mesh.ply + project.mlp (rasters with photos/ paths relative to CAPTURE), as made by
#              the capture tools (bench/capture on the capture branch)
#     K: default 5;  OUT_DIR: default $BUILD_DIR/meshlab-projection/<capture name>
#     DEPTH: the filter's "depth threshold" (deptheta), in scene units: a point farther than this
#            behind the surface a camera sees still takes that camera's colour. Default 0.5, MeshLab's
#            own default, which on an object 1-2 units across lets colours through thin parts (an
#            ear, a trunk); pass about 1 % of the bounding-box diagonal for MeshLab at its best.
# Writes OUT_DIR/train.mlp, OUT_DIR/meshlab_colors.ply, OUT_DIR/meshlab.log; prints meshlabserver's
# wall time (loading + projection + saving), the filter's own time from MeshLab's log, and the
# wall time of loading only (so projection ~ difference).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
PREFIX="${MESHLAB_PREFIX:-$BUILD_DIR/meshlab-prefix}"
CAP="$(cd "$1" && pwd)"; K="${2:-5}"; DEPTH="${4:-0.5}"
OUT="${3:-$BUILD_DIR/meshlab-projection/$(basename "$CAP")}"
mkdir -p "$OUT/config/VCG"
OUT="$(cd "$OUT" && pwd)"
export XDG_CONFIG_HOME="$OUT/config"
# MeshLab's GUI default GPU-memory budget, as bench/fit_vs_meshlab.sh.
printf '[General]\nMeshLab::System::maxGPUMemDedicatedToGeometry=350\n' >"$OUT/config/VCG/MeshLab_64bit_fp.conf"
# Training rasters only; image paths made absolute (the project lives elsewhere now).
awk -v k="$K" -v cap="$CAP" '
  /<MLRaster/ { n++; skip = (n % k == 0) }
  { gsub(/fileName="photos\//, "fileName=\"" cap "/photos/") }
  !skip { print }
  /<\/MLRaster>/ { skip = 0 }' "$CAP/project.mlp" >"$OUT/train.mlp"
BUILD_DIR="$BUILD_DIR" bash "$REPO/scripts/filter_script.sh" --out "$OUT/projection.mlx" \
    --filter "Project active rasters color to current mesh" deptheta="$DEPTH" onselection=false useangle=true \
    usedistance=true useborders=true usesilhouettes=true usealpha=false blankColor=0,0,0,255
server() { /usr/bin/time -f "%e s wall, %M KB peak" xvfb-run -a -s "-screen 0 1280x1024x24" "$PREFIX/bin/meshlabserver" "$@"; }
echo "depth threshold: $DEPTH"
echo "rasters: $(grep -c '<MLRaster' "$OUT/train.mlp") of $(grep -c '<MLRaster' "$CAP/project.mlp") (every ${K}th left out)"
server -i "$CAP/mesh.ply" -p "$OUT/train.mlp" >"$OUT/load.log" 2>&1
echo "loading only: $(tail -n 1 "$OUT/load.log")"
server -i "$CAP/mesh.ply" -p "$OUT/train.mlp" -s "$OUT/projection.mlx" -o "$OUT/meshlab_colors.ply" -m vc vn \
    >"$OUT/meshlab.log" 2>&1
echo "loading + projection: $(tail -n 1 "$OUT/meshlab.log")"
grep -iE "applied filter|msec|secs" "$OUT/meshlab.log" | tail -n 3 || true
echo "colours: $OUT/meshlab_colors.ply"
