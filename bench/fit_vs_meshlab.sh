#!/usr/bin/env bash
# Speed of "Fit Radiance Functions from Rasters" on a large project, side by side with MeshLab's own
# "Project active rasters color to current mesh" on the same project, both through meshlabserver.
#   bench/fit_vs_meshlab.sh [VIEWS] [WxH] [SUBDIVIDE]   (defaults: 50 views, 2048x1536, 3 levels)
# The mesh: the CGAL armadillo scan (26,002 vertices) midpoint-subdivided 3 times = 1,662,722
# vertices. Photographs: virtual_acquisition (glossy material, shadows), 2x2 supersampling.
# Printed: meshlabserver wall time of (a) loading only, (b) loading + our fit (PB4), (c) loading +
# MeshLab's colour projection, and the filter times from the logs. Not part of CI (minutes).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
VIEWS="${1:-50}"; SIZE="${2:-2048x1536}"; LEVELS="${3:-3}"
WORK="${WORK:-$BUILD_DIR/bench-fit-vs-meshlab}"
mkdir -p "$WORK/config"
WORK="$(cd "$WORK" && pwd)"
export XDG_CONFIG_HOME="$WORK/config"
# MeshLab's GUI default GPU-memory budget (350 MB) so its GL-based filter runs with buffer objects
# (docs: meshlabserver reads the budget from the GUI's settings).
mkdir -p "$WORK/config/VCG"
printf '[General]\nMeshLab::System::maxGPUMemDedicatedToGeometry=350\n' >"$WORK/config/VCG/MeshLab_64bit_fp.conf"
PREFIX="$BUILD_DIR/meshlab-prefix"
server() { /usr/bin/time -f "%e s wall, %M KB peak" xvfb-run -a -s "-screen 0 1280x1024x24" "$PREFIX/bin/meshlabserver" "$@"; }

if [ ! -f "$WORK/photos/project.mlp" ]; then
    "$BUILD_DIR/tools/virtual_acquisition" "$REPO/data-cache/meshes/armadillo.off" -o "$WORK/photos" \
        --views "$VIEWS" --size "$SIZE" --subdivide "$LEVELS" --material glossy | tail -n 3
fi
bash "$REPO/scripts/write_fit_mlx.sh" "$WORK/fit.mlx" 0.05
BUILD_DIR="$BUILD_DIR" bash "$REPO/scripts/filter_script.sh" --out "$WORK/meshlab_projection.mlx" \
    --filter "Project active rasters color to current mesh" deptheta=0.5 onselection=false useangle=true \
    usedistance=true useborders=true usesilhouettes=true usealpha=false blankColor=0,0,0,255
args=(-i "$WORK/photos/mesh.ply" -p "$WORK/photos/project.mlp")
echo "== loading only (mesh + $VIEWS rasters)"
server "${args[@]}" >"$WORK/load.log" 2>&1; tail -n 1 "$WORK/load.log"
echo "== loading + Fit Radiance Functions from Rasters (PB4)"
server "${args[@]}" -s "$WORK/fit.mlx" -o "$WORK/fit.rply" -m vc vq vn >"$WORK/fit.log" 2>&1
grep -h "Fitted" "$WORK/fit.log" | tail -n 1; tail -n 1 "$WORK/fit.log"
echo "== loading + Project active rasters color to current mesh (MeshLab)"
server "${args[@]}" -s "$WORK/meshlab_projection.mlx" -o "$WORK/meshlab_colors.ply" -m vc >"$WORK/meshlab.log" 2>&1
tail -n 1 "$WORK/meshlab.log"
