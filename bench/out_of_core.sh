#!/usr/bin/env bash
# Figures of the out-of-core simplification (Granier et al. 2007, Lindstrom 2000). Not part of CI
# (tens of minutes, several GB of disk).
#   bench/out_of_core.sh [big|compare|meshlab|all]      (default all)
#   big      the CGAL armadillo (52,000 triangles) with every triangle cut into 44 x 44 = 100.7 M
#            triangles, written STREAMING as a binary PLY (~2.5 GB) into $WORK, reduced to about
#            BIG_TARGET (default 1,000,000) triangles with a 4096^2 normal map and a BIG_GUTTER-texel
#            gutter (default 0: the triangles edge to edge, the only gutter with which 1 M triangles
#            fit a 4096^2 per-triangle atlas, docs/out-of-core.md) by tools/simplify_out_of_core
#            under /usr/bin/time -v (peak RSS, wall time, M triangles/s); the PLY is deleted afterwards.
#   compare  the same scan cut 8 x 8 (3.3 M triangles): the streamed map vs the in-core bake
#            (bakeNormalMapFiles, object space, the same simplified mesh and UVs): mean / p95 degrees
#            over the texels whose centre is inside a triangle (bench_out_of_core compare).
#   meshlab  throughput on that 3.3 M-triangle mesh: ours (read + cluster + map) vs meshlabserver
#            loading the PLY and running its Quadric Edge Collapse Decimation to the same count.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
WORK="${WORK:-$BUILD_DIR/bench-out-of-core}"
WHAT="${1:-all}"
mkdir -p "$WORK/config"
WORK="$(cd "$WORK" && pwd)"
export XDG_CONFIG_HOME="$WORK/config"
BENCH="$BUILD_DIR/bench/bench_out_of_core"
TOOL="$BUILD_DIR/tools/simplify_out_of_core"
ARMADILLO="$REPO/data-cache/meshes/armadillo.off"
timed() { /usr/bin/time -f "%e s wall, %M KB peak" "$@"; }

mid_mesh() {
    [ -f "$WORK/armadillo_3M.ply" ] || "$BENCH" generate "$ARMADILLO" 8 "$WORK/armadillo_3M.ply"
}

if [ "$WHAT" = big ] || [ "$WHAT" = all ]; then
    echo "== 100 M triangles: generate (streaming)"
    timed "$BENCH" generate "$ARMADILLO" 44 "$WORK/armadillo_100M.ply"
    ls -l "$WORK/armadillo_100M.ply"
    BIG_TARGET="${BIG_TARGET:-1000000}"
    BIG_GUTTER="${BIG_GUTTER:-0}"
    echo "== 100 M triangles -> $BIG_TARGET, 4096^2 map, $BIG_GUTTER-texel gutter"
    /usr/bin/time -v "$TOOL" "$WORK/armadillo_100M.ply" "$WORK/big" --target "$BIG_TARGET" --texture-size 4096 \
        --gutter "$BIG_GUTTER" --quiet 2>"$WORK/big.time" || { cat "$WORK/big.time"; rm -f "$WORK/armadillo_100M.ply"; exit 1; }
    grep -E "Maximum resident|Elapsed \(wall|Percent of CPU" "$WORK/big.time"
    rm -f "$WORK/armadillo_100M.ply"
fi

if [ "$WHAT" = compare ] || [ "$WHAT" = all ]; then
    mid_mesh
    for case in "30000 2048" "100000 4096"; do
        set -- $case
        echo "== streamed vs in-core bake: 3.3 M triangles -> $1, ${2}^2 map"
        "$BENCH" compare "$WORK/armadillo_3M.ply" "$1" "$2" "$WORK/compare_$1"
    done
fi

if [ "$WHAT" = meshlab ] || [ "$WHAT" = all ]; then
    mid_mesh
    PREFIX="$BUILD_DIR/meshlab-prefix"
    TARGET=330000
    echo "== ours: 3.3 M triangles -> $TARGET (read, cluster, 4096^2 map with a 1-texel gutter, write)"
    timed "$TOOL" "$WORK/armadillo_3M.ply" "$WORK/ours_3M" --target "$TARGET" --texture-size 4096 --gutter 1 --quiet | \
        grep -E "time:|simplified:"
    cat >"$WORK/meshlab_qem.mlx" <<MLX
<!DOCTYPE FilterScript>
<FilterScript>
$(bash "$REPO/scripts/meshlab_decimation_filter.sh" "$TARGET" false false)
</FilterScript>
MLX
    echo "== meshlabserver: load + save only"
    timed xvfb-run -a -s "-screen 0 1280x1024x24" "$PREFIX/bin/meshlabserver" -i "$WORK/armadillo_3M.ply" \
        -o "$WORK/meshlab_copy.ply" >"$WORK/load.log" 2>&1 || true; tail -n 1 "$WORK/load.log"
    echo "== meshlabserver: load + Quadric Edge Collapse Decimation to $TARGET + save"
    timed xvfb-run -a -s "-screen 0 1280x1024x24" "$PREFIX/bin/meshlabserver" -i "$WORK/armadillo_3M.ply" \
        -s "$WORK/meshlab_qem.mlx" -o "$WORK/meshlab_qem.ply" >"$WORK/qem.log" 2>&1 || true
    grep -h -i "simplif\|decimat\|applied" "$WORK/qem.log" | tail -n 2 || true; tail -n 1 "$WORK/qem.log"
fi
