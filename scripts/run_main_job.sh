#!/usr/bin/env bash
# The README's first command: sets everything up, then runs the main job on real data.
# Main job: a real scan (the CGAL bunny, 37,706 vertices) is photographed virtually (40 calibrated
# photographs of a glossy, spatially varying material with cast shadows, written as a MeshLab
# project), the project is opened in Debian's real meshlabserver (mesh with -i, rasters with -p),
# our filter "Fit Radiance Functions from Rasters" fits PB(4) radiance functions, the result is
# saved in the radiance PLY format, and a picture compares a photograph with the fitted radiance
# rendered from the same camera (photo | rendering | 4x difference).
# Outputs go to out/ (override with OUT_DIR).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
OUT_DIR="${OUT_DIR:-$REPO/out}"
DATA="${RADIANCE_DATA_CACHE:-$REPO/data-cache}"
export BUILD_DIR

bash "$REPO/scripts/setup.sh"
mkdir -p "$OUT_DIR/config"
OUT_DIR="$(cd "$OUT_DIR" && pwd)"   # meshlabserver changes directory to the project's
export XDG_CONFIG_HOME="$OUT_DIR/config"   # never touch the user's MeshLab settings
PREFIX="$BUILD_DIR/meshlab-prefix"
server() { xvfb-run -a -s "-screen 0 1280x1024x24" "$PREFIX/bin/meshlabserver" "$@"; }
elapsed() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}'; }

SCAN="$DATA/meshes/bunny00.off"
[ -f "$SCAN" ] || { echo "missing $SCAN: run samples/fetch_data.sh" >&2; exit 1; }

echo "[main] photographing $(basename "$SCAN") virtually: 40 views of 1024x768"
"$BUILD_DIR/tools/virtual_acquisition" "$SCAN" -o "$OUT_DIR/bunny_photos" --views 40 --size 1024x768 \
    --material glossy >"$OUT_DIR/acquisition.log"
tail -n 3 "$OUT_DIR/acquisition.log"

bash "$REPO/scripts/write_fit_mlx.sh" "$OUT_DIR/fit.mlx" 0.0002

echo "[main] fitting PB(4) radiance functions in meshlabserver"
start=$(date +%s.%N)
server -i "$OUT_DIR/bunny_photos/mesh.ply" -p "$OUT_DIR/bunny_photos/project.mlp" -s "$OUT_DIR/fit.mlx" \
    -o "$OUT_DIR/bunny_radiance.rply" -m vc vq vn -l "$OUT_DIR/fit.log" >"$OUT_DIR/fit.stdout" 2>&1
echo "[main] $(grep -h "Fitted" "$OUT_DIR/fit.log" | tail -n 1) (meshlabserver wall $(elapsed "$start") s)"

echo "[main] rendering the fitted radiance from the camera of photograph 7"
"$BUILD_DIR/tools/render_radiance" "$OUT_DIR/bunny_radiance.rply" --project "$OUT_DIR/bunny_photos/project.mlp" \
    --view 7 --mode fragment -o "$OUT_DIR/bunny_fit_view07.png" --compare raster \
    --side-by-side "$OUT_DIR/bunny_photo_vs_fit_view07.png"
"$BUILD_DIR/tools/radiance_info" "$OUT_DIR/bunny_radiance.rply"
echo "[main] outputs:"
ls -l "$OUT_DIR"/*.rply "$OUT_DIR"/*.png
echo "[main] picture (photograph | fitted radiance | 4x difference): $OUT_DIR/bunny_photo_vs_fit_view07.png"
echo "[main] open the fit with: $PREFIX/bin/meshlab $OUT_DIR/bunny_radiance.rply"
