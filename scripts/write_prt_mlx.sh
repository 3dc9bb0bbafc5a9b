#!/usr/bin/env bash
# write_prt_mlx.sh OUT.mlx STEP [STEP...]: a meshlabserver script running the PRT filters in order,
# each with every parameter listed, as meshlabserver 2020.09 requires. Steps:
#   transfer:ORDER:RAYS[:OCCLUDERS(0 mesh|1 visible layers)[:ALBEDO(true|false)]]
#   adaptive:FACTOR[:MEASURE(0 eq.2|1 eq.3|2 eq.4|3 probed (default)|4 probed absolute)[:ALPHA[:THRESHOLD[:BUDGET]]]]
#   uniform:FACTOR[:BUDGET]
#   relight-dir:X:Y:Z[:INTENSITY]
#   relight-env:FILE[:ROTATION_DEGREES[:UP(0 +X|1 +Y|2 +Z)]]   (the map at intensity 1)
# FACTOR: budget as a multiple of the face count (0: use BUDGET, an absolute face count).
set -euo pipefail
out="$1"; shift
{
echo '<!DOCTYPE FilterScript>'
echo '<FilterScript>'
for step in "$@"; do
    IFS=: read -r kind a b c d e f <<<"$step"
    case "$kind" in
    transfer)
        cat <<MLX
 <filter name="Radiance: Compute PRT Transfer">
  <Param type="RichInt" name="order" value="${a:-6}"/>
  <Param type="RichInt" name="rays" value="${b:-256}"/>
  <Param type="RichEnum" name="occluders" value="${c:-0}" enum_cardinality="2" enum_val0="mesh" enum_val1="visible"/>
  <Param type="RichBool" name="albedo" value="${d:-false}"/>
  <Param type="RichFloat" name="rayOffset" value="0.0001"/>
 </filter>
MLX
        ;;
    adaptive)
        cat <<MLX
 <filter name="Radiance: Adaptive PRT Subdivision">
  <Param type="RichInt" name="budget" value="${e:-0}"/>
  <Param type="RichFloat" name="budgetFactor" value="${a:-4}"/>
  <Param type="RichEnum" name="measure" value="${b:-3}" enum_cardinality="5" enum_val0="eq2" enum_val1="eq3" enum_val2="eq4" enum_val3="probed" enum_val4="probed-absolute"/>
  <Param type="RichFloat" name="alpha" value="${c:-4}"/>
  <Param type="RichFloat" name="threshold" value="${d:-0}"/>
 </filter>
MLX
        ;;
    uniform)
        cat <<MLX
 <filter name="Radiance: Uniform PRT Subdivision">
  <Param type="RichInt" name="budget" value="${b:-0}"/>
  <Param type="RichFloat" name="budgetFactor" value="${a:-4}"/>
  <Param type="RichEnum" name="measure" value="2" enum_cardinality="5" enum_val0="eq2" enum_val1="eq3" enum_val2="eq4" enum_val3="probed" enum_val4="probed-absolute"/>
  <Param type="RichFloat" name="alpha" value="4"/>
 </filter>
MLX
        ;;
    relight-dir|relight-env)
        if [ "$kind" = relight-dir ]; then lighting=1; map=""; x="$a"; y="$b"; z="$c"; intensity="${d:-3}"; rot=0; up=2
        else lighting=0; map="$a"; x=0.5; y=0.5; z=1; intensity=1; rot="${b:-0}"; up="${c:-2}"; fi
        cat <<MLX
 <filter name="Radiance: PRT Relighting as Vertex Color">
  <Param type="RichEnum" name="lighting" value="$lighting" enum_cardinality="2" enum_val0="map" enum_val1="directional"/>
  <Param type="RichString" name="environmentMap" value="$map"/>
  <Param type="RichFloat" name="rotation" value="$rot"/>
  <Param type="RichEnum" name="upAxis" value="$up" enum_cardinality="3" enum_val0="x" enum_val1="y" enum_val2="z"/>
  <Param type="RichPoint3f" name="lightDirection" x="$x" y="$y" z="$z"/>
  <Param type="RichFloat" name="lightIntensity" value="$intensity"/>
  <Param type="RichFloat" name="exposure" value="1"/>
 </filter>
MLX
        ;;
    *) echo "write_prt_mlx.sh: unknown step '$step'" >&2; exit 2 ;;
    esac
done
echo '</FilterScript>'
} >"$out"
