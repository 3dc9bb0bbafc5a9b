#!/usr/bin/env bash
# Prints the <filter> element of MeshLab's "Simplification: Quadric Edge Collapse Decimation" with
# every parameter meshlabserver 2020.09 requires, for embedding in .mlx scripts (the baseline and
# the simplified targets of the normal-map bakes).
# Usage: meshlab_decimation_filter.sh TARGET_FACES [PRESERVE_TOPOLOGY(true|false, default false)]
#                                     [PRESERVE_NORMAL(true|false, default true)]
set -euo pipefail
faces="${1:?usage: meshlab_decimation_filter.sh TARGET_FACES [PRESERVE_TOPOLOGY]}"
topology="${2:-false}"
normal="${3:-true}"
cat <<XML
 <filter name="Simplification: Quadric Edge Collapse Decimation">
  <Param type="RichInt" name="TargetFaceNum" value="$faces"/>
  <Param type="RichFloat" name="TargetPerc" value="0"/>
  <Param type="RichFloat" name="QualityThr" value="0.3"/>
  <Param type="RichBool" name="PreserveBoundary" value="false"/>
  <Param type="RichFloat" name="BoundaryWeight" value="1"/>
  <Param type="RichBool" name="PreserveNormal" value="$normal"/>
  <Param type="RichBool" name="PreserveTopology" value="$topology"/>
  <Param type="RichBool" name="OptimalPlacement" value="true"/>
  <Param type="RichBool" name="PlanarQuadric" value="false"/>
  <Param type="RichFloat" name="PlanarWeight" value="0.001"/>
  <Param type="RichBool" name="QualityWeight" value="false"/>
  <Param type="RichBool" name="AutoClean" value="true"/>
  <Param type="RichBool" name="Selected" value="false"/>
 </filter>
XML
