#!/usr/bin/env bash
# GUI test of Vanhoey et al. 2015 Fig. 6 in MeshLab: the toy quad (4 vertices, normals diverging outwards)
# with the RF of a narrow Blinn-Phong lobe lit along its normal (make_fig6_quad) is shown by the
# decoration per vertex, then per fragment (two MeshLab sessions). In front of the quad, the lobe's
# peak is seen only through the per-fragment interpolation of eq. 8, near the centre; the vertices
# themselves all look dark. The quad's centre and four points inside its corners are located in the
# screenshot through the view file (probe_decoration_view: the camera of the GL matrices), not at
# fixed pixels, and fig6_contrast.sh judges (margin 40 luma levels, stated there):
#   - per fragment: the centre is brighter than every corner region by the margin (a highlight inside);
#   - per vertex: it is not (no highlight can appear between dark vertices).
# Each session is also compared with the CPU reference (figures printed, not asserted here).
# Usage: gui_fig6_highlight.sh
source "$(dirname "$0")/../integration/lib.sh"
source "$(dirname "$0")/gui_lib.sh"

"$MAKE_FIG6_QUAD" -o "$WORK/quad.rply"
start_xvfb
declare -A contrast
for mode in 0 1; do
    name="$([ "$mode" = 0 ] && echo per-vertex || echo per-fragment)"
    write_decoration_settings "$mode" 0 0
    start_meshlab "$name" "$WORK/quad.rply"
    show_decoration "$name"
    check_decoration_log "$name"
    check_view_mode "$name" "$name"
    stop_meshlab
    out="$(bash "$(dirname "$0")/fig6_contrast.sh" measure "$PROBE_DECORATION_VIEW" "$WORK/$name.view-at-shot.txt" \
        "$WORK/$name.png")" || { echo "$out" >&2; fail "$name: the quad's points could not be probed"; }
    echo "$out"
    contrast[$name]="$(awk '/^contrast/{ print $2 }' <<<"$out")"
    "$COMPARE_DECORATION_VIEW" --mesh "$WORK/quad.rply" --view "$WORK/$name.view-at-shot.txt" \
        --screenshot "$WORK/$name.png" --shading "$name" --exclude-bottom "$INFO_PANEL_ROWS" \
        --out-diff "$WORK/$name.diff.png" --out-reference "$WORK/$name.reference.png" \
        | sed "s/^/[$name vs CPU] /" || note "$name: no comparison with the CPU reference"
done
bash "$(dirname "$0")/fig6_contrast.sh" judge "${contrast[per-vertex]}" "${contrast[per-fragment]}" \
    || fail "Fig. 6 not reproduced (screenshots $WORK/per-vertex.png, $WORK/per-fragment.png)"
note "ok: contrast per vertex ${contrast[per-vertex]}, per fragment ${contrast[per-fragment]}"
