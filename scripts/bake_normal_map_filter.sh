#!/usr/bin/env bash
# Prints the <filter> element of our "Bake Normal Map" (every parameter, from the filter's own list),
# for embedding in .mlx scripts (tests, the MeshLab comparison bench, the main job).
# Usage: bake_normal_map_filter.sh SOURCE_INDEX SIZE SPACE(0 object|1 tangent) BITS(0=16|1=8)
#                                  NEW_ATLAS(true|false) DIFFUSE(true|false) [OUTPUT_PNG]
#                                  [TANGENT_FRAME(0 MikkTSpace|1 per-face), default 0]
#                                  [GLTF(true|false), default false: also write <base>.glb]
#                                  [name=value...: any other parameter of the filter]
# Maximum ray distance automatic, gutter 4, LEAN on, the normal map as the layer's texture.
set -euo pipefail
[ $# -ge 6 ] || { echo "usage: $0 SOURCE SIZE SPACE BITS NEW_ATLAS DIFFUSE [OUTPUT]" >&2; exit 2; }
source="$1" size="$2" space="$3" bits="$4" atlas="$5" diffuse="$6" output="${7:-}" frame="${8:-0}" gltf="${9:-false}"
shift $(( $# < 9 ? $# : 9 ))
bash "$(dirname "$0")/filter_script.sh" --layers "$((source + 1))" --elements-only --out - --filter "Bake Normal Map" \
    sourceMesh="$source" textureSize="$size" space="$space" tangentFrame="$frame" bits="$bits" maxDistance=0 \
    gutter=4 newAtlas="$atlas" diffuse="$diffuse" lean=true gltf="$gltf" assign=0 outputFile="$output" "$@"
