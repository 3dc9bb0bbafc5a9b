#!/usr/bin/env bash
# write_fit_mlx.sh OUT.mlx [DEPTH_TOLERANCE] [DEGREE]: a meshlabserver script running "Radiance: Fit
# Radiance Functions from Rasters" (PB basis) with every parameter listed, as meshlabserver 2020.09
# requires. DEPTH_TOLERANCE in scene units (default 0.0002), DEGREE default 4.
set -euo pipefail
out="$1"; tolerance="${2:-0.0002}"; degree="${3:-4}"
cat >"$out" <<MLX
<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Radiance: Fit Radiance Functions from Rasters">
  <Param type="RichBool" name="visibleOnly" value="false"/>
  <Param type="RichEnum" name="basis" value="0" enum_cardinality="2" enum_val0="PB" enum_val1="SH"/>
  <Param type="RichInt" name="degree" value="$degree"/>
  <Param type="RichFloat" name="regularization" value="0.001"/>
  <Param type="RichAbsPerc" name="depthTolerance" value="$tolerance" min="0" max="1000"/>
  <Param type="RichFloat" name="grazingAngle" value="80"/>
  <Param type="RichInt" name="borderMargin" value="2"/>
  <Param type="RichInt" name="minSamples" value="3"/>
  <Param type="RichBool" name="reflected" value="false"/>
  <Param type="RichEnum" name="quality" value="0" enum_cardinality="2" enum_val0="count" enum_val1="residual"/>
  <Param type="RichBool" name="setColor" value="true"/>
  <Param type="RichBool" name="validation" value="true"/>
  <Param type="RichBool" name="robust" value="true"/>
  <Param type="RichBool" name="exposureCompensation" value="true"/>
  <Param type="RichEnum" name="fitModel" value="0" enum_cardinality="3" enum_val0="automatic" enum_val1="pervertex" enum_val2="shared"/>
  <Param type="RichInt" name="heldOutEvery" value="0"/>
 </filter>
</FilterScript>
MLX
