#!/usr/bin/env bash
# Speed and memory of radiance-aware simplification on a large scan, side by side with MeshLab's own
# geometry-only "Simplification: Quadric Edge Collapse Decimation" on the same mesh and ratio.
#   bench/simplify_vs_meshlab.sh [RATIO] [SUBDIVIDE]     (defaults: 0.1, 3 levels)
# The mesh: the CGAL armadillo scan (26,002 vertices) midpoint-subdivided 3 times = 1,664,002
# vertices, 3,328,000 faces, with the exact PB4 radiance of the glossy sample material (cast
# shadows, smooth variation) from make_radiance_mesh. Printed, each with wall time and peak memory:
#   (a) simplify_radiance (our core, one process: read .rply, simplify, write the level);
#   (b) meshlabserver: loading + saving only; (c) loading + MeshLab's quadric decimation + saving;
#   (d) loading + our "Radiance: Radiance-Aware Simplification" filter + saving.
# The in-filter times come from the logs. Not part of CI (minutes).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
RATIO="${1:-0.1}"; LEVELS="${2:-3}"
WORK="${WORK:-$BUILD_DIR/bench-simplify}"
mkdir -p "$WORK/config"
WORK="$(cd "$WORK" && pwd)"
export XDG_CONFIG_HOME="$WORK/config"
PREFIX="$BUILD_DIR/meshlab-prefix"
timed() { /usr/bin/time -f "%e s wall, %M KB peak" "$@"; }
server() { timed xvfb-run -a -s "-screen 0 1280x1024x24" "$PREFIX/bin/meshlabserver" "$@"; }

MESH="$WORK/armadillo_pb4.rply"
if [ ! -f "$MESH" ]; then
    "$BUILD_DIR/tools/make_radiance_mesh" "$REPO/data-cache/meshes/armadillo.off" --subdivide "$LEVELS" \
        --basis PB4 -o "$MESH"
fi
# MeshLab's own PLY importer reads the same file (it skips the radiance properties).
ln -sf "$MESH" "$WORK/armadillo_plain.ply"
FACES=$(grep -a -m1 "^element face" "$MESH" | awk '{print $3}')
TARGET=$(python3 -c "print(int($FACES * $RATIO))")
echo "mesh: $MESH, $FACES faces, target $TARGET faces (ratio $RATIO)"

echo "== (a) simplify_radiance, radiance metric (eq. 7), half-edge collapse"
timed "$BUILD_DIR/tools/simplify_radiance" "$MESH" -o "$WORK/ours" --ratios "$RATIO" 2>&1 | tail -n 4
echo "== (a') simplify_radiance, geometry only (memoryless QEM), half-edge collapse"
timed "$BUILD_DIR/tools/simplify_radiance" "$MESH" -o "$WORK/ours_geometry" --ratios "$RATIO" --metric geometry 2>&1 | tail -n 3

cat >"$WORK/meshlab_qem.mlx" <<MLX
<!DOCTYPE FilterScript>
<FilterScript>
$(bash "$REPO/scripts/meshlab_decimation_filter.sh" "$TARGET" false false)
</FilterScript>
MLX
echo "== (b) meshlabserver: load + save only"
server -i "$WORK/armadillo_plain.ply" -o "$WORK/meshlab_copy.ply" >"$WORK/load.log" 2>&1; tail -n 1 "$WORK/load.log"
echo "== (c) meshlabserver: load + Quadric Edge Collapse Decimation (MeshLab, geometry only) + save"
server -i "$WORK/armadillo_plain.ply" -s "$WORK/meshlab_qem.mlx" -o "$WORK/meshlab_qem.ply" >"$WORK/qem.log" 2>&1
grep -h -i "simplif\|decimat" "$WORK/qem.log" | tail -n 2 || true; tail -n 1 "$WORK/qem.log"
if [ -f "$REPO/scripts/write_simplify_mlx.sh" ]; then
    bash "$REPO/scripts/write_simplify_mlx.sh" "$WORK/ours.mlx" "$RATIO"
    echo "== (d) meshlabserver: load + Radiance-Aware Simplification (ours) + save"
    server -i "$MESH" -s "$WORK/ours.mlx" -o "$WORK/ours_filter.rply" >"$WORK/ours.log" 2>&1
    grep -h "Simplified" "$WORK/ours.log" | tail -n 1 || true; tail -n 1 "$WORK/ours.log"
fi
