#!/usr/bin/env bash
# GUI test of the "Radiance Field" decoration against the CPU reference renderer: Debian's real
# meshlab (private prefix) under Xvfb opens a radiance file with private settings selecting the
# shading, exposure and tone curve; the trackball is hidden, the view reset, the decoration turned on
# (Ctrl+Alt+R); a screenshot taken while the decoration's view file describes the screen is compared
# (compare_decoration_view) with the CPU rendering of the same camera, shading and tone mapping on the
# pixels the mesh covers (eroded by 2 px; MeshLab's info panel excluded). Asserts
#   - rmse < BOUND 8-bit levels (proposed: 3 for a smooth sphere, per vertex and per fragment: GL
#     floats and rasterisation against the ray caster's doubles; to be set from measurements),
#   - the decoration drew in the requested mode (the settings were read),
#   - MeshLab's log has no "GL error" and has the decoration's "Radiance Field ..." start line.
# Mode 2 (PRT relighting) needs transfer vectors in INPUT; the reference relights them with the
# decoration's default light (directional, toward (0, 1, 1), intensity 1, no rotation).
# Usage: gui_decoration.sh INPUT.rply MODE(0=per vertex|1=per fragment|2=PRT) BOUND [EXPOSURE_STOPS] [TONEMAP(0|1)]
source "$(dirname "$0")/../integration/lib.sh"
source "$(dirname "$0")/gui_lib.sh"
input="$1"; mode="$2"; bound="$3"; exposure="${4:-0}"; tone="${5:-0}"; extra=()
case "$mode" in
0) mode_name=per-vertex ;;
1) mode_name=per-fragment ;;
2) mode_name=prt; extra=(--vertex-colors-from-prt 0,1,1,1) ;;
*) fail "MODE must be 0 (per vertex), 1 (per fragment) or 2 (PRT), got '$mode'" ;;
esac
[ -s "$input" ] || fail "no input $input"

start_xvfb
write_decoration_settings "$mode" "$exposure" "$tone"
start_meshlab decoration "$input"
show_decoration decoration
check_decoration_log decoration
check_view_mode decoration "$mode_name"

out="$("$COMPARE_DECORATION_VIEW" --mesh "$input" --view "$WORK/decoration.view-at-shot.txt" \
    --screenshot "$WORK/decoration.png" --shading "$mode_name" "${extra[@]}" --erode 2 --exclude-bottom "$INFO_PANEL_ROWS" \
    --out-diff "$WORK/diff.png" --out-reference "$WORK/reference.png" --out-crop "$WORK/crop.png")" \
    || { echo "$out" >&2; fail "compare_decoration_view failed (see above)"; }
echo "$out"
rmse="$(awk '/^pixels /{ print $4 }' <<<"$out")"
awk -v r="$rmse" -v b="$bound" 'BEGIN { exit !(r < b) }' \
    || fail "$mode_name: rmse $rmse 8-bit levels >= $bound against the CPU reference (crop $WORK/crop.png, reference $WORK/reference.png, 4 x difference $WORK/diff.png)"
stop_meshlab
note "ok: $mode_name rmse $rmse < $bound"
