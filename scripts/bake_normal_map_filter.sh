#!/usr/bin/env bash
# Prints the <filter> element of our "Bake Normal Map" with every parameter meshlabserver 2020.09
# requires, for embedding in .mlx scripts (tests, the MeshLab comparison bench, the main job).
# Usage: bake_normal_map_filter.sh SOURCE_INDEX SIZE SPACE(0 object|1 tangent) BITS(0=16|1=8)
#                                  NEW_ATLAS(true|false) DIFFUSE(true|false) [OUTPUT_PNG]
#                                  [TANGENT_FRAME(0 MikkTSpace|1 per-face), default 0]
#                                  [GLTF(true|false), default false: also write <base>.glb]
# Maximum ray distance automatic, gutter 4, LEAN on, the normal map as the layer's texture.
set -euo pipefail
[ $# -ge 6 ] || { echo "usage: $0 SOURCE SIZE SPACE BITS NEW_ATLAS DIFFUSE [OUTPUT]" >&2; exit 2; }
source="$1" size="$2" space="$3" bits="$4" atlas="$5" diffuse="$6" output="${7:-}" frame="${8:-0}" gltf="${9:-false}"
cat <<XML
 <filter name="Bake Normal Map">
  <Param type="RichMesh" name="sourceMesh" value="$source"/>
  <Param type="RichInt" name="textureSize" value="$size"/>
  <Param type="RichEnum" name="space" value="$space" enum_cardinality="2" enum_val0="Object space" enum_val1="Tangent space"/>
  <Param type="RichEnum" name="tangentFrame" value="$frame" enum_cardinality="2" enum_val0="MikkTSpace (Blender, glTF, Unity, Unreal)" enum_val1="Per-face dP/du (old)"/>
  <Param type="RichEnum" name="bits" value="$bits" enum_cardinality="2" enum_val0="16 bit" enum_val1="8 bit"/>
  <Param type="RichAbsPerc" name="maxDistance" value="0" min="0" max="1000000"/>
  <Param type="RichInt" name="gutter" value="4"/>
  <Param type="RichBool" name="newAtlas" value="$atlas"/>
  <Param type="RichBool" name="diffuse" value="$diffuse"/>
  <Param type="RichBool" name="lean" value="true"/>
  <Param type="RichBool" name="gltf" value="$gltf"/>
  <Param type="RichFloat" name="gltfRoughness" value="0.5"/>
  <Param type="RichEnum" name="assign" value="0" enum_cardinality="2" enum_val0="Normal map" enum_val1="Diffuse map"/>
  <Param type="RichString" name="outputFile" value="$output"/>
 </filter>
XML
