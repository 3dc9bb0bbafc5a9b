# Sourced by the bake tests: bake_mlx FILE SOURCE_INDEX SIZE SPACE(0 object|1 tangent) BITS(0=16|1=8)
#   [NEW_ATLAS(true|false)] [OUTPUT] [TANGENT_FRAME(0|1)] [GLTF(true|false)] : a one-filter script running "Bake Normal Map" with every
# parameter listed (scripts/bake_normal_map_filter.sh), diffuse map on.
bake_mlx() {
    local file="$1" source="$2" size="$3" space="$4" bits="$5" atlas="${6:-false}" output="${7:-}" frame="${8:-0}" gltf="${9:-false}"
    {
        echo '<!DOCTYPE FilterScript>'
        echo '<FilterScript>'
        bash "$RADIANCE_SOURCE_DIR/scripts/bake_normal_map_filter.sh" "$source" "$size" "$space" "$bits" "$atlas" true "$output" "$frame" "$gltf"
        echo '</FilterScript>'
    } >"$file"
}
