#!/usr/bin/env bash
# Speed of the PRT transfer computation on a large scan, side by side with MeshLab's own "Ambient
# Occlusion" filter (per-vertex, depth maps rendered from N views: an approximation of visibility,
# where ours casts exact rays), both through meshlabserver on the same mesh.
#   bench/prt_vs_meshlab_ao.sh [SUBDIVIDE] [RAYS] [AO_VIEWS]     (defaults: 3 levels, 256, 128)
# The mesh: the CGAL armadillo scan (26,002 vertices) midpoint-subdivided 3 times = 1,664,002
# vertices (the bench/simplify_vs_meshlab.sh mesh without radiance). Printed: wall time and peak
# memory of (a) load + save, (b) load + MeshLab AO (CPU mode: no GPU here) + save, (c) load + our
# "Radiance: Compute PRT Transfer" (SH order 6, RAYS rays) + save; the filters' own times from their
# logs and the useful vertex-directions per second of each. Also (d) bench_prt_transfer: our
# transfer against a raw Embree loop shooting the same rays. Not part of CI (minutes).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
LEVELS="${1:-3}"; RAYS="${2:-256}"; VIEWS="${3:-128}"
WORK="${WORK:-$BUILD_DIR/bench-prt}"
mkdir -p "$WORK/config"
WORK="$(cd "$WORK" && pwd)"
export XDG_CONFIG_HOME="$WORK/config"
PREFIX="$BUILD_DIR/meshlab-prefix"
timed() { /usr/bin/time -f "%e s wall, %M KB peak" "$@"; }
server() { timed xvfb-run -a -s "-screen 0 1280x1024x24" "$PREFIX/bin/meshlabserver" "$@"; }

SOURCE="$WORK/armadillo_x$LEVELS.rply"
if [ ! -f "$SOURCE" ]; then
    # (PB0: the smallest radiance payload; MeshLab's PLY importer skips it and reads positions, normals.)
    "$BUILD_DIR/tools/make_radiance_mesh" "$REPO/data-cache/meshes/armadillo.off" --subdivide "$LEVELS" \
        --basis PB0 --no-shadows -o "$SOURCE" >/dev/null
fi
MESH="$WORK/armadillo_x$LEVELS.ply"
ln -sf "$SOURCE" "$MESH"
VERTICES=$(grep -a -m1 "^element vertex" "$MESH" | awk '{print $3}')
echo "mesh: $MESH, $VERTICES vertices"

export BUILD_DIR
bash "$REPO/scripts/filter_script.sh" --out "$WORK/ao.mlx" --filter "Ambient Occlusion" occMode=0 dirBias=0 \
    reqViews="$VIEWS" coneDir=0,1,0 coneAngle=30 useGPU=false depthTexSize=512
bash "$REPO/scripts/write_prt_mlx.sh" "$WORK/prt.mlx" "transfer:6:$RAYS"

echo "== (a) meshlabserver: load + save only"
server -i "$MESH" -o "$WORK/plain_out.ply" -m vn 2>&1 | tail -n 1
echo "== (b) meshlabserver: load + Ambient Occlusion ($VIEWS views, per vertex) + save"
start=$(date +%s.%N)
server -i "$MESH" -s "$WORK/ao.mlx" -o "$WORK/ao_out.ply" -m vq vc >"$WORK/ao.log" 2>&1 || true
tail -n 1 "$WORK/ao.log"
grep -a "Ambient Occlusion\|LOG:" "$WORK/ao.log" | tail -n 3 || true
echo "== (c) meshlabserver: load + Compute PRT Transfer (order 6, $RAYS rays) + save"
server -i "$MESH" -s "$WORK/prt.mlx" -o "$WORK/prt_out.ply" -m vq vc >"$WORK/prt.log" 2>&1 || true
tail -n 1 "$WORK/prt.log"
grep -a "Computed PRT" "$WORK/prt.log" | tail -n 1 || true
python3 - "$WORK/ao.log" "$WORK/prt.log" "$VERTICES" "$VIEWS" "$RAYS" <<'PY'
import re, sys
ao_log, prt_log, n, views, rays = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
def wall(path):
    m = re.findall(r"([0-9.]+) s wall", open(path, errors="replace").read())
    return float(m[-1]) if m else float("nan")
ao, prt = wall(ao_log), wall(prt_log)
print("vertex-directions per second (whole meshlabserver run): MeshLab AO %.2f M (%d views), ours %.2f M (%d rays)"
      % (n * views / ao / 1e6, views, n * rays / prt / 1e6, rays))
PY
echo "== (d) bench_prt_transfer: ours vs a raw Embree loop, same rays"
"$BUILD_DIR/bench/bench_prt_transfer" "$REPO/data-cache/meshes/armadillo.off" --subdivide "$LEVELS" --rays "$RAYS"
