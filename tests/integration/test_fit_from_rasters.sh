#!/usr/bin/env bash
# "Fit Radiance Functions from Rasters" on a MeshLab project of virtual photographs, through the
# real meshlabserver (mesh with -i, rasters with -p, as a user's photogrammetry project):
#  - the log reports the counts; the saved .rply holds PB4 radiance;
#  - evaluated toward each camera, the fitted functions reproduce the photographs at the vertices'
#    projections (checked by an independent Python implementation of the .mlp camera model);
#  - the reflected and SH variants run and save, and the vertex quality holds the sample counts.
source "$(dirname "$0")/lib.sh"
CHECK_FIT="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_fit_against_photos.py"

"$MAKE_SCENE" sphere --level 4 -o "$WORK/sphere.ply"
"$VIRTUAL_ACQUISITION" "$WORK/sphere.ply" -o "$WORK/photos" --views 16 --size 320x240 --no-variation \
    >"$WORK/acquisition.log" 2>&1 || { cat "$WORK/acquisition.log" >&2; fail "virtual acquisition failed"; }

# fit_photos NAME: runs $WORK/fit_NAME.mlx on the photographs' project into $WORK/fit_NAME.rply
# (log $WORK/NAME.log); fit_logged NAME GREP_ARGS...: the log has that line.
fit_photos() {
    run_meshlabserver "$WORK/$1.log" -i "$WORK/photos/mesh.ply" -p "$WORK/photos/project.mlp" \
        -s "$WORK/fit_$1.mlx" -o "$WORK/fit_$1.rply" -m vc vq vn || { cat "$WORK/$1.log" >&2; fail "$1 fit failed"; }
}
fit_logged() {
    local name="$1"
    shift
    grep -q "$@" "$WORK/$name.log" || { cat "$WORK/$name.log" >&2; fail "$name: no line matching $*"; }
}

fit_mlx "$WORK/fit_pb4.mlx" 0 4 false 0
fit_photos pb4
fit_logged pb4 -E "Fitted PB4 radiance functions on 2562 vertices from 16 of 16 rasters in [0-9.]+ s: [0-9]+ samples, median [0-9]+ per seen vertex"
# Median and 90th percentile of |fitted - photo| in 8-bit sRGB levels over vertex-view pairs.
$CHECK_FIT "$WORK/fit_pb4.rply" "$WORK/photos/project.mlp" 2 8 || fail "fitted functions do not reproduce the photographs"

# Vertex quality = sample count: every vertex of a sphere seen from 16 directions all around is
# seen several times, and no vertex by more than the 16 photographs.
python3 - "$WORK/fit_pb4.rply" "$PLY_READER" <<'PY' || fail "vertex quality is not a sample count"
import sys, importlib.util
spec = importlib.util.spec_from_file_location("ply_reader", sys.argv[2]); r = importlib.util.module_from_spec(spec); spec.loader.exec_module(r)
q = r.read_ply(sys.argv[1])["elements"]["vertex"]["quality"]
assert all(float(x).is_integer() and 1 <= x <= 16 for x in q), (min(q), max(q))
assert sum(q) / len(q) > 3, sum(q) / len(q)
print(f"sample counts {min(q):.0f}..{max(q):.0f}, mean {sum(q) / len(q):.1f}")
PY

# The filter's automatic model choice through meshlabserver (here it takes the shared fit: the log
# says which): its functions, written into PB4 in each vertex's frame, must still show the
# photographs (a wrong frame, reflection or channel order gives errors of tens of levels). The
# shared fit does not interpolate its samples as the per-vertex fit does: a median of 3 levels.
# Without validation and Huber weights, as above: with them a highlight seen by one photograph
# counts as an outlier, by design, and the 90th percentile measures those highlights instead.
fit_mlx "$WORK/fit_auto.mlx" 0 4 false 0 false false 0
fit_photos auto
fit_logged auto -E "Fit model chosen on every 5-th raster left out .*: (shared|per vertex);"
$CHECK_FIT "$WORK/fit_auto.rply" "$WORK/photos/project.mlp" 3 8 || fail "the automatic fit does not show the photographs"

fit_mlx "$WORK/fit_sh.mlx" 1 3 true 1
fit_photos sh
fit_logged sh -F "Fitted SH3 radiance functions (reflected)"
python3 "$PLY_READER" --summary "$WORK/fit_sh.rply" | grep "radiance_basis SH3" >/dev/null || fail "SH3 radiance not saved"
note "ok"
