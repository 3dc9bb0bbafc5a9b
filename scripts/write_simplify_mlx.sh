#!/usr/bin/env bash
# write_simplify_mlx.sh OUT.mlx PERCENTAGE [METRIC] [LOD_LEVELS] [PROGRESSIVE_FILE] [COLLAPSE]: a
# meshlabserver script running "Radiance: Radiance-Aware Simplification" with every parameter listed,
# as meshlabserver 2020.09 requires. PERCENTAGE: target as a fraction of the faces (e.g. 0.1);
# METRIC: 0 radiance (default), 1 light field 2010, 2 colour QEM, 3 geometry; LOD_LEVELS e.g.
# "0.5 0.25"; PROGRESSIVE_FILE an absolute .rpm path or empty; COLLAPSE 0 half-edge, 1 full.
set -euo pipefail
out="$1"; percentage="$2"; metric="${3:-0}"; lods="${4:-}"; progressive="${5:-}"; collapse="${6:-0}"
cat >"$out" <<MLX
<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Radiance: Radiance-Aware Simplification">
  <Param type="RichEnum" name="metric" value="$metric" enum_cardinality="5" enum_val0="radiance" enum_val1="lightfield" enum_val2="color" enum_val3="geometry" enum_val4="radiancequadric"/>
  <Param type="RichEnum" name="collapse" value="$collapse" enum_cardinality="2" enum_val0="half" enum_val1="full"/>
  <Param type="RichInt" name="targetFaces" value="0"/>
  <Param type="RichFloat" name="targetPercentage" value="$percentage"/>
  <Param type="RichString" name="lodLevels" value="$lods"/>
  <Param type="RichFloat" name="geometryWeight" value="0.01"/>
  <Param type="RichFloat" name="attributeWeight" value="0.99"/>
  <Param type="RichBool" name="preserveBoundary" value="true"/>
  <Param type="RichInt" name="minValence" value="0"/>
  <Param type="RichInt" name="maxValence" value="0"/>
  <Param type="RichFloat" name="maxNormalChange" value="90"/>
  <Param type="RichBool" name="lazy" value="true"/>
  <Param type="RichString" name="progressiveFile" value="$progressive"/>
 </filter>
</FilterScript>
MLX
