#!/usr/bin/env bash
# GUI test of the "Irradiance Vector Grid" decoration (Granier et al. 2007) in Debian's real meshlab
# under Xvfb. make_analytic_ivg writes a white sphere (sphere.ply) and, beside it, sphere.ivg: an
# analytic two-colour field, red light from the +x side, green light from the -x side (not blue:
# MeshLab's background is blue). meshlab opens
# the sphere, the view is reset (Ctrl+H: +x to the right) and the decoration turned on (Ctrl+Alt+I).
# Asserts
#   - the decoration's start line names the grid beside the layer, and no GL error;
#   - the picture shows the field: thousands of red and of green pixels, the red ones right of the
#     green ones; MeshLab's own rendering of the white sphere has neither;
#   - "Direct + indirect" (private settings) changes the picture (the direct light adds to it);
#   - a truncated .ivg beside another copy of the sphere: the log says why (the reader's "truncated
#     file"), meshlab keeps running and nothing red or green is drawn; no .ivg at all: the log says so;
#     the grid named in the options (relative: beside the layer) is drawn on that layer;
#   - Granier et al. 2007's case, a simplified mesh with a baked normal map: the armadillo scan
#     simplified by MeshLab to 1,000 faces and its normals baked by our filter (as gui_normal_map.sh),
#     a grid over its box, light mostly from above: the decoration says it evaluates the grid with the baked normal map, and
#     the picture differs from the one with the vertex normals: more than 3,000 pixels by more than 5 %
#     (13 levels; the scan's detail; the armadillo covers about 35,000 pixels, measured 9,509).
source "$(dirname "$0")/../integration/lib.sh"
source "$(dirname "$0")/gui_lib.sh"
MAKE_IVG="$RADIANCE_BUILD_DIR/tools/make_analytic_ivg"
SIDES="$RADIANCE_SOURCE_DIR/tests/gui/ivg_colour_sides.py"
[ -x "$MAKE_IVG" ] || fail "no $MAKE_IVG (build the tools)"
"$MAKE_IVG" -o "$WORK/sphere" --radius 1 --cells 8 --radiance 0.9 >/dev/null || fail "make_analytic_ivg failed"
cp "$WORK/sphere.ply" "$WORK/bad.ply"
head -c 2000 "$WORK/sphere.ivg" >"$WORK/bad.ivg"
cp "$WORK/sphere.ply" "$WORK/nogrid.ply"
# The 3D view (the window is 1200 x 900 at the screen's corner; left of the layer panel, below the
# toolbars, above MeshLab's info panel).
CROP="10 90 760 640"

start_xvfb
settings() {  # settings LIGHT(0|1) [NORMALS(0 map|1 vertex)] [GRID_FILE]
    mkdir -p "$XDG_CONFIG_HOME/VCG"
    cat >"$XDG_CONFIG_HOME/VCG/MeshLab_64bit_fp.conf" <<CONF
[General]
MeshLab%3A%3ADecoration%3A%3AIrradianceGridLight="<!DOCTYPE MeshLabSettings>\n<Param type=\"RichEnum\" value=\"$1\" name=\"MeshLab::Decoration::IrradianceGridLight\" enum_cardinality=\"2\" enum_val0=\"Indirect\" enum_val1=\"Direct + indirect\"/>\n"
MeshLab%3A%3ADecoration%3A%3AIrradianceGridNormals="<!DOCTYPE MeshLabSettings>\n<Param type=\"RichEnum\" value=\"${2:-0}\" name=\"MeshLab::Decoration::IrradianceGridNormals\" enum_cardinality=\"2\" enum_val0=\"Normal map\" enum_val1=\"Vertex normals\"/>\n"
MeshLab%3A%3ADecoration%3A%3AIrradianceGridFile="<!DOCTYPE MeshLabSettings>\n<Param type=\"RichOpenFile\" value=\"${3:-}\" name=\"MeshLab::Decoration::IrradianceGridFile\" exts_cardinality=\"1\" ext_val0=\"*.ivg\"/>\n"
CONF
}
shot() {  # shot NAME INPUT DECORATE(1|0)
    local name="$1" input="$2" decorate="$3"
    start_meshlab "$name" "$input"
    # Sized again: under load the first resize (start_meshlab) is sometimes applied only in part,
    # and the pictures are compared over the same crop of the 3D view.
    xdotool windowsize "$window" 1200 900 2>/dev/null || true
    sleep 1
    if [ "$decorate" = 1 ]; then keys shift+h ctrl+h ctrl+alt+i; else keys shift+h ctrl+h; fi
    sleep 6
    kill -0 "$meshlab_pid" 2>/dev/null || { tail -n 30 "$WORK/$name.meshlab.log" >&2; fail "$name: meshlab died"; }
    import -window root "$WORK/$name.png"
    stop_meshlab
    if grep -n "GL error" "$WORK/$name.meshlab.log"; then fail "$name: GL error"; fi
}
sides() { python3 "$SIDES" "$WORK/$1.png" $CROP; }

settings 0
shot plain "$WORK/sphere.ply" 0
shot indirect "$WORK/sphere.ply" 1
grep -E "Irradiance Vector Grid: layer .*grid '.*sphere\.ivg', 8 x 8 x 8 cells" "$WORK/indirect.meshlab.log" \
    || { grep -i "irradiance" "$WORK/indirect.meshlab.log" >&2; fail "indirect: the decoration did not start on sphere.ivg"; }
read -r _ red_n red_x _ green_n green_x <<<"$(sides indirect)"
read -r _ plain_red _ _ plain_green _ <<<"$(sides plain)"
note "indirect only: $red_n red pixels (mean column $red_x), $green_n green (mean column $green_x); MeshLab's own: $plain_red red, $plain_green green"
[ "$red_n" -gt 5000 ] && [ "$green_n" -gt 5000 ] || fail "the field's two colours are not on the sphere"
awk -v r="$red_x" -v b="$green_x" 'BEGIN { exit !(r > b + 50) }' || fail "red is not right (+x) of green"
[ "$plain_red" -lt 100 ] && [ "$plain_green" -lt 100 ] || fail "MeshLab's own rendering already has the colours?"

settings 1
shot direct "$WORK/sphere.ply" 1
rmse() {
    { compare -metric RMSE "$1"[760x640+10+90] "$2"[760x640+10+90] null: 2>&1 || true; } |
        sed -E 's/.*\(([0-9.e-]+)\).*/\1/' | awk '{ printf "%.2f", $1 * 255 }'
}
d="$(rmse "$WORK/indirect.png" "$WORK/direct.png")"
note "RMSE indirect vs direct + indirect: $d levels"
awk -v d="$d" 'BEGIN { exit !(d > 5) }' || fail "the direct light changes nothing (RMSE $d)"
read -r _ direct_red _ _ direct_green _ <<<"$(sides direct)"
note "direct + indirect: $direct_red red, $direct_green green saturated pixels (the white direct light pales them)"
[ $((direct_red + direct_green)) -lt $(((red_n + green_n) / 2)) ] || fail "the direct light does not pale the colours"

settings 0
shot bad "$WORK/bad.ply" 1
grep -E "Irradiance Vector Grid: not started on layer .*bad\.ivg.*truncated file" "$WORK/bad.meshlab.log" \
    || { grep -i "irradiance" "$WORK/bad.meshlab.log" >&2; fail "bad: no log line with the reader's reason"; }
[ "$(grep -c "Irradiance Vector Grid: not started" "$WORK/bad.meshlab.log")" -eq 1 ] || fail "bad: the message is not logged once"
read -r _ bad_red _ _ bad_green _ <<<"$(sides bad)"
[ "$bad_red" -lt 100 ] && [ "$bad_green" -lt 100 ] || fail "bad: something was drawn ($bad_red red, $bad_green green)"
shot nogrid "$WORK/nogrid.ply" 1
grep -E "Irradiance Vector Grid: not started on layer .*no irradiance vector grid '.*nogrid\.ivg'" "$WORK/nogrid.meshlab.log" \
    || { grep -i "irradiance" "$WORK/nogrid.meshlab.log" >&2; fail "nogrid: no log line"; }
# The same layer with the grid named in the options (a relative name: beside the layer's file).
settings 0 0 sphere.ivg
shot named "$WORK/nogrid.ply" 1
grep -qE "Irradiance Vector Grid: layer 'nogrid.ply', grid '.*/sphere\.ivg'" "$WORK/named.meshlab.log" \
    || { grep -i "irradiance" "$WORK/named.meshlab.log" >&2; fail "named: the grid file of the options was not used"; }
read -r _ named_red _ _ named_green _ <<<"$(sides named)"
note "grid named in the options: $named_red red, $named_green green"
[ "$named_red" -gt 5000 ] && [ "$named_green" -gt 5000 ] || fail "named: the field's colours are not on the sphere"

# The simplified armadillo with its baked normal map, and a grid over its box.
bake_armadillo 1024
"$MAKE_IVG" -o "$WORK/armadillo_baked" --fit "$WORK/armadillo_baked.ply" --cells 6 --from-above >/dev/null || fail "no grid for the armadillo"
settings 0 0
shot mapped "$WORK/armadillo_baked.ply" 1
grep -E "Irradiance Vector Grid: layer .*armadillo_baked\.ivg', 6 x 6 x 6 cells.*the baked 1024x1024 normal map" \
    "$WORK/mapped.meshlab.log" || { grep -i "irradiance" "$WORK/mapped.meshlab.log" >&2; fail "mapped: not drawn with the normal map"; }
read -r _ map_red map_red_x _ map_green map_green_x <<<"$(sides mapped)"
note "armadillo, normal map: $map_red red (mean column $map_red_x), $map_green green (mean column $map_green_x)"
[ "$map_red" -gt 1000 ] && [ "$map_green" -gt 1000 ] || fail "mapped: the field's colours are not on the armadillo"
awk -v r="$map_red_x" -v b="$map_green_x" 'BEGIN { exit !(r > b) }' || fail "mapped: red is not right (+x) of green"
settings 0 1
shot vertexnormals "$WORK/armadillo_baked.ply" 1
grep -qE "Irradiance Vector Grid: layer .*vertex normals" "$WORK/vertexnormals.meshlab.log" || fail "vertexnormals: the option was not read"
d_map="$({ compare -metric AE -fuzz 5% "$WORK/mapped.png"[760x640+10+90] "$WORK/vertexnormals.png"[760x640+10+90] null: 2>&1 || true; } | awk '{ print int($1) }')"
note "armadillo: $d_map pixels differ by more than 5 % between the normal map and the vertex normals"
[ "$d_map" -gt 3000 ] || fail "the normal map does not change the indirect light ($d_map pixels differ)"
note "ok"
