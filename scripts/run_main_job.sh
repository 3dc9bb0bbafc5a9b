#!/usr/bin/env bash
# The README's first command: sets everything up, then runs the main job on real data.
# Main job: a real scan (the CGAL bunny, 37,706 vertices) is photographed virtually (40 calibrated
# photographs of a glossy, spatially varying material with cast shadows, written as a MeshLab
# project), the project is opened in Debian's real meshlabserver (mesh with -i, rasters with -p),
# our filter "Fit Radiance Functions from Rasters" fits PB(4) radiance functions, the result is
# saved in the radiance PLY format, and a picture compares a photograph with the fitted radiance
# rendered from the same camera (photo | rendering | 4x difference). The fitted mesh is then
# simplified (radiance-aware, with levels of detail) and compared in image space with the colour and
# geometry baselines and with directional reduction: table, heat maps and an error-memory plot.
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

# Simplification (paper 000 sec. 4): the fitted mesh through our filter in meshlabserver to 25 % of
# its faces, recording the progressive mesh; levels of detail replayed from it; the baselines (colour
# QEM on the mean colour, geometry only) and directional reduction at similar memory; all rendered
# from 16 views against the fitted original (per-fragment eq. 8): table, heat maps, plot.
echo "[main] radiance-aware simplification of the fitted mesh in meshlabserver (25 %, progressive)"
SIMP="$OUT_DIR/simplification"
mkdir -p "$SIMP"
# (the extra levels make the recording go down to 5 %; meshlabserver saves the current layer only)
bash "$REPO/scripts/write_simplify_mlx.sh" "$OUT_DIR/simplify.mlx" 0.25 0 "0.5 0.1 0.05" "$SIMP/bunny.rpm"
server -i "$OUT_DIR/bunny_radiance.rply" -s "$OUT_DIR/simplify.mlx" -o "$OUT_DIR/bunny_radiance_25.rply" \
    >"$OUT_DIR/simplify.log" 2>&1
echo "[main] $(grep -h "^LOG: .*Simplified" "$OUT_DIR/simplify.log" | tail -n 1 | sed 's/^LOG: [0-9] //')"
"$BUILD_DIR/tools/simplify_radiance" "$SIMP/bunny.rpm" -o "$SIMP/radiance" --ratios 0.5,0.25,0.1,0.05 >/dev/null
# Garland-Heckbert's 6D quadric holds the geometric distance itself: no extra geometry term.
"$BUILD_DIR/tools/simplify_radiance" "$OUT_DIR/bunny_radiance.rply" -o "$SIMP/color" --metric color \
    --geometry-weight 0 --attribute-weight 1 --ratios 0.5,0.25,0.1,0.05 >/dev/null
"$BUILD_DIR/tools/simplify_radiance" "$OUT_DIR/bunny_radiance.rply" -o "$SIMP/geometry" --metric geometry \
    --ratios 0.5,0.25,0.1,0.05 >/dev/null
for basis in PB3 PB2 PB1 PB0; do
    "$BUILD_DIR/tools/simplify_radiance" "$OUT_DIR/bunny_radiance.rply" -o "$SIMP/directional" --reduce "$basis" >/dev/null
done
echo "[main] image-space comparison (16 views, 512x512, per-fragment shading)"
"$BUILD_DIR/tools/compare_radiance_meshes" "$OUT_DIR/bunny_radiance.rply" \
    "$SIMP"/radiance_*.rply "$SIMP"/color_*.rply "$SIMP"/geometry_*.rply "$SIMP"/directional_*.rply \
    --up 0,1,0 --heatmaps "$SIMP/heatmaps" | tee "$OUT_DIR/simplification_errors.txt"
python3 "$REPO/scripts/plot_error_vs_memory.py" "$OUT_DIR/simplification_errors.txt" \
    "$OUT_DIR/simplification_error_vs_memory.svg" "Fitted bunny: image error against memory"
# Precomputed radiance transfer (paper 001): the column on a plane through our filters in
# meshlabserver (transfer, adaptive subdivision with the error estimate as face colour, relighting),
# then adaptive against uniform subdivision at the same triangle count on the column and on the
# (simplified) bunny scan standing on a plane: relighting error over 32 directional lights and four
# HDR maps in four rotations each, pictures against a per-pixel ray-cast reference.
echo "[main] PRT: column on a plane through meshlabserver (transfer, adaptive subdivision, relighting)"
PRT="$OUT_DIR/prt"
mkdir -p "$PRT"
"$BUILD_DIR/tools/make_scene" column -o "$PRT/column.ply"
bash "$REPO/scripts/write_prt_mlx.sh" "$PRT/column.mlx" transfer:6:256 adaptive:4 relight-dir:1:0.3:0.8:3
server -i "$PRT/column.ply" -s "$PRT/column.mlx" -o "$PRT/column_adaptive.rply" -m vc vn \
    -o "$PRT/column_adaptive_error.ply" -m fc fq >"$PRT/column.log" 2>&1
grep -h "^LOG: .*\(Computed PRT\|Adaptive PRT\|Relit\)" "$PRT/column.log" | sed 's/^LOG: [0-9] /[main] /'
HDRS=()
for map in city courtyard forest studio; do HDRS+=(--hdr "$DATA/hdr/$map.exr"); done
echo "[main] PRT: adaptive vs uniform subdivision, column scene (paper 001 Fig. 1)"
"$BUILD_DIR/tools/evaluate_prt" --scene column --levels 2 "${HDRS[@]}" --out "$PRT/column" \
    | tee "$OUT_DIR/prt_column_errors.txt"
echo "[main] PRT: adaptive vs uniform subdivision, bunny scan (simplified to 2000 faces) on a plane"
"$BUILD_DIR/tools/evaluate_prt" --mesh "$DATA/meshes/bunny00.off" --up y --simplify-to 2000 --levels 2 \
    "${HDRS[@]}" --out "$PRT/bunny" | tee "$OUT_DIR/prt_bunny_errors.txt"
# Normal-map baking (papers 004, 002): the fitted scan simplified by MeshLab to 2 % and its normals
# and colours baked onto the simplified mesh by "Bake Normal Map" (per-triangle atlas, 2048^2,
# object space, 16 bit, LEAN moments), in one meshlabserver run; then the map's angular error
# against the scan's normals (tools/normal_map_error).
echo "[main] normal map: bunny scan simplified to 2 % (1,508 faces), scan normals and colours baked onto it"
BAKE="$OUT_DIR/bake"
mkdir -p "$BAKE"
cat >"$BAKE/simplify_and_bake.mlx" <<MLX
<!DOCTYPE FilterScript>
<FilterScript>
$(bash "$REPO/scripts/meshlab_decimation_filter.sh" 1508 false)
 <filter name="Re-Compute Vertex Normals">
  <Param type="RichEnum" name="weightMode" value="2" enum_cardinality="4" enum_val0="Simple Average" enum_val1="By Angle" enum_val2="By Area" enum_val3="As defined by N. Max"/>
 </filter>
$(bash "$REPO/scripts/bake_normal_map_filter.sh" 0 2048 0 0 true true "$BAKE/bunny_2pct_normal.png")
</FilterScript>
MLX
server -i "$OUT_DIR/bunny_radiance.rply" -i "$OUT_DIR/bunny_radiance.rply" -s "$BAKE/simplify_and_bake.mlx" \
    -o "$BAKE/bunny_2pct.ply" -m wt vn -o "$BAKE/bunny_2pct.obj" -m wt vn >"$BAKE/bake.log" 2>&1
grep -h -o "LOG: 2 Bake Normal Map: .*" "$BAKE/bake.log" | sed 's/^LOG: [0-9] /[main] /'
"$BUILD_DIR/tools/normal_map_error" "$OUT_DIR/bunny_radiance.rply" "$BAKE/bunny_2pct.obj" "$BAKE/bunny_2pct_normal.png" \
    2>&1 | tee "$OUT_DIR/normal_map_error.txt" || true
echo "[main] outputs:"
ls -l "$OUT_DIR"/*.rply "$OUT_DIR"/*.png "$OUT_DIR"/*.svg
echo "[main] picture (photograph | fitted radiance | 4x difference): $OUT_DIR/bunny_photo_vs_fit_view07.png"
echo "[main] simplification: $OUT_DIR/simplification_errors.txt, $OUT_DIR/simplification_error_vs_memory.svg,"
echo "       heat maps in $SIMP/heatmaps (radiance_100 vs color_100: 10 % of the faces)"
echo "[main] PRT: $OUT_DIR/prt_column_errors.txt, $OUT_DIR/prt_bunny_errors.txt; pictures in $PRT/column and"
echo "       $PRT/bunny (reference.png = per-pixel transfer; input/uniform/adaptive.png = interpolated)"
echo "[main] normal map: $BAKE/bunny_2pct_{normal,diffuse}.png, _lean.exr; error in $OUT_DIR/normal_map_error.txt; see it with"
echo "       $PREFIX/bin/meshlab $BAKE/bunny_2pct.ply, then Ctrl+Alt+N (Baked Normal Map decoration)"
echo "[main] open the fit with: $PREFIX/bin/meshlab $OUT_DIR/bunny_radiance.rply"
