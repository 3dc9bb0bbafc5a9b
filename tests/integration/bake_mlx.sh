# Sourced by the bake tests: bake_mlx FILE SOURCE_INDEX SIZE SPACE(0 object|1 tangent) BITS(0=16|1=8)
#   [NEW_ATLAS(true|false)] [OUTPUT] : a script running "Bake Normal Map" with every parameter listed
# (meshlabserver 2020.09 aborts when one is missing).
bake_mlx() {
    local file="$1" source="$2" size="$3" space="$4" bits="$5" atlas="${6:-false}" output="${7:-}"
    write_mlx "$file" "Bake Normal Map" \
        "<Param type=\"RichMesh\" name=\"sourceMesh\" value=\"$source\"/>" \
        "<Param type=\"RichInt\" name=\"textureSize\" value=\"$size\"/>" \
        "<Param type=\"RichEnum\" name=\"space\" value=\"$space\" enum_cardinality=\"2\" enum_val0=\"Object space\" enum_val1=\"Tangent space\"/>" \
        "<Param type=\"RichEnum\" name=\"bits\" value=\"$bits\" enum_cardinality=\"2\" enum_val0=\"16 bit\" enum_val1=\"8 bit\"/>" \
        '<Param type="RichAbsPerc" name="maxDistance" value="0" min="0" max="10"/>' \
        '<Param type="RichInt" name="gutter" value="4"/>' \
        "<Param type=\"RichBool\" name=\"newAtlas\" value=\"$atlas\"/>" \
        '<Param type="RichBool" name="diffuse" value="true"/>' \
        '<Param type="RichBool" name="lean" value="true"/>' \
        '<Param type="RichEnum" name="assign" value="0" enum_cardinality="2" enum_val0="Normal map" enum_val1="Diffuse map"/>' \
        "<Param type=\"RichString\" name=\"outputFile\" value=\"$output\"/>"
}
