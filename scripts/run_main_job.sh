#!/usr/bin/env bash
# The README's first command: sets everything up, then runs the main job on real data.
# Today's main job: a real scan (the CGAL bunny, 37,706 vertices) gets view-dependent radiance
# functions from a glossy striped material through Debian's real meshlabserver and our plugins, is
# saved in the radiance PLY format, reloaded, and evaluated toward a viewpoint as vertex colours.
# Outputs go to out/ (override with OUT_DIR).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
OUT_DIR="${OUT_DIR:-$REPO/out}"
DATA="${RADIANCE_DATA_CACHE:-$REPO/data-cache}"
export BUILD_DIR

bash "$REPO/scripts/setup.sh"
mkdir -p "$OUT_DIR/config"
export XDG_CONFIG_HOME="$OUT_DIR/config"   # never touch the user's MeshLab settings
PREFIX="$BUILD_DIR/meshlab-prefix"
server() { xvfb-run -a -s "-screen 0 1280x1024x24" "$PREFIX/bin/meshlabserver" "$@"; }

SCAN="$DATA/meshes/bunny00.off"
[ -f "$SCAN" ] || { echo "missing $SCAN: run samples/fetch_data.sh" >&2; exit 1; }

cat >"$OUT_DIR/create_radiance.mlx" <<'MLX'
<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Radiance: Create Radiance Data from Analytic Material">
  <Param type="RichEnum" name="basis" value="0" enum_cardinality="2" enum_val0="PB" enum_val1="SH"/>
  <Param type="RichInt" name="degree" value="4"/>
  <Param type="RichBool" name="reflected" value="false"/>
  <Param type="RichColor" name="albedo" r="200" g="150" b="90" a="255"/>
  <Param type="RichColor" name="specularColor" r="255" g="255" b="255" a="255"/>
  <Param type="RichFloat" name="specular" value="0.5"/>
  <Param type="RichFloat" name="shininess" value="60"/>
  <Param type="RichInt" name="stripes" value="8"/>
  <Param type="RichEnum" name="stripeAxis" value="1" enum_cardinality="3" enum_val0="X" enum_val1="Y" enum_val2="Z"/>
  <Param type="RichEnum" name="lightType" value="0" enum_cardinality="2" enum_val0="Directional" enum_val1="Point"/>
  <Param type="RichPoint3f" name="light" x="0.4" y="1" z="0.8"/>
  <Param type="RichFloat" name="lightIntensity" value="3"/>
  <Param type="RichFloat" name="ambient" value="0.05"/>
  <Param type="RichBool" name="setColor" value="true"/>
 </filter>
</FilterScript>
MLX
cat >"$OUT_DIR/evaluate_view.mlx" <<'MLX'
<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color">
  <Param type="RichPoint3f" name="viewpoint" x="0" y="0.1" z="1"/>
  <Param type="RichFloat" name="exposure" value="1"/>
 </filter>
</FilterScript>
MLX

echo "[main] creating PB(4) radiance functions on $(basename "$SCAN")"
start=$(date +%s.%N)
server -i "$SCAN" -o "$OUT_DIR/bunny_radiance.rply" -m vc vn -s "$OUT_DIR/create_radiance.mlx" \
    -l "$OUT_DIR/create.log" >"$OUT_DIR/create.stdout" 2>&1
echo "[main] $(grep -h "Created" "$OUT_DIR/create.log" || true) (meshlabserver wall $(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s)"
echo "[main] reloading the .rply and evaluating it toward a viewpoint"
server -i "$OUT_DIR/bunny_radiance.rply" -o "$OUT_DIR/bunny_view_colors.ply" -m vc vn -s "$OUT_DIR/evaluate_view.mlx" \
    -l "$OUT_DIR/evaluate.log" >"$OUT_DIR/evaluate.stdout" 2>&1
"$BUILD_DIR/tools/radiance_info" "$OUT_DIR/bunny_radiance.rply"
echo "[main] outputs:"
ls -l "$OUT_DIR"/*.rply "$OUT_DIR"/*.ply
echo "[main] open them with: $PREFIX/bin/meshlab $OUT_DIR/bunny_radiance.rply"
