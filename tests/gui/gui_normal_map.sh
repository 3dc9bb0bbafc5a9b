#!/usr/bin/env bash
# GUI test of the "Baked Normal Map" decoration in Debian's real meshlab under Xvfb. The armadillo
# scan is simplified by MeshLab (Quadric Edge Collapse, 1,000 faces) and the scan's normals are
# baked onto it by our filter, in one meshlabserver run; meshlab then opens the baked layer three
# times with private settings selecting the shading (vertex normals, normal map, LEAN), the view
# reset (Ctrl+H) and the decoration turned on (Ctrl+Alt+N). Asserts
#   - the decoration's start line (object-space map, LEAN on) and no GL error in MeshLab's log,
#   - the normal map changes the picture: RMSE(vertex normals, normal map) > 4 levels over the
#     3D view (the scan's detail on 1,000 faces),
#   - the three pictures are not MeshLab's own rendering (decoration drawn).
source "$(dirname "$0")/../integration/lib.sh"
source "$(dirname "$0")/gui_lib.sh"
bake_armadillo 1024
[ -s "$WORK/armadillo_normal.png" ] && [ -s "$WORK/armadillo_lean.exr" ] || fail "the bake wrote no map"

start_xvfb
shot() {  # shot NAME SHADING(0|1|2) [DECORATE(1|0)]
    local name="$1" shading="$2" decorate="${3:-1}"
    mkdir -p "$XDG_CONFIG_HOME/VCG"
    cat >"$XDG_CONFIG_HOME/VCG/MeshLab_64bit_fp.conf" <<CONF
[General]
MeshLab%3A%3ADecoration%3A%3ANormalMapShading="<!DOCTYPE MeshLabSettings>\n<Param type=\"RichEnum\" value=\"$shading\" name=\"MeshLab::Decoration::NormalMapShading\" enum_cardinality=\"3\" enum_val0=\"Vertex normals\" enum_val1=\"Normal map\" enum_val2=\"LEAN\"/>\n"
CONF
    start_meshlab "$name" "$WORK/armadillo_baked.ply"
    if [ "$decorate" = 1 ]; then keys shift+h ctrl+h ctrl+alt+n; else keys shift+h ctrl+h; fi
    sleep 6
    import -window root "$WORK/$name.png"
    stop_meshlab
    if grep -n "GL error" "$WORK/$name.meshlab.log"; then fail "$name: GL error"; fi
    if [ "$decorate" = 1 ]; then
        grep -qF "Baked Normal Map: layer" "$WORK/$name.meshlab.log" \
            || { tail -n 30 "$WORK/$name.meshlab.log" >&2; fail "$name: the decoration did not start"; }
        grep -qE "Baked Normal Map: layer .*object-space 1024x1024 map, LEAN on" "$WORK/$name.meshlab.log" \
            || { grep "Baked Normal Map" "$WORK/$name.meshlab.log" >&2; fail "$name: not an object-space map with LEAN"; }
    fi
}
# RMSE in 8-bit levels over the 3D view (the window is 1200 x 900 at the screen's corner; the view
# is left of the layer panel, below the toolbars, above MeshLab's info panel). `compare` exits 1
# when the images differ, which is the point here.
rmse() {
    { compare -metric RMSE "$1"[760x640+10+90] "$2"[760x640+10+90] null: 2>&1 || true; } |
        sed -E 's/.*\(([0-9.e-]+)\).*/\1/' | awk '{ printf "%.2f", $1 * 255 }'
}

shot plain 0 0
shot vertex 0
shot normal 1
shot lean 2
d_map="$(rmse "$WORK/vertex.png" "$WORK/normal.png")"
d_plain_vertex="$(rmse "$WORK/plain.png" "$WORK/vertex.png")"
d_plain_lean="$(rmse "$WORK/plain.png" "$WORK/lean.png")"
note "RMSE (8-bit levels): vertex normals vs normal map $d_map; MeshLab's own vs vertex normals $d_plain_vertex, vs LEAN $d_plain_lean"
awk -v d="$d_map" 'BEGIN { exit !(d > 4) }' || fail "the normal map does not change the picture (RMSE $d_map)"
awk -v a="$d_plain_vertex" -v b="$d_plain_lean" 'BEGIN { exit !(a > 1 && b > 1) }' || fail "the decoration drew nothing"
note "ok"
