#!/usr/bin/env bash
# The Fig. 6 highlight measure and judgement shared by gui_fig6_highlight.sh and the dry run.
#
#   fig6_contrast.sh measure PROBE VIEW.txt SHOT.png [HALF_SIZE]
#     Probes (probe_decoration_view) the screenshot around the quad's centre (0, 0, 0) and four
#     points on its diagonals at 0.7 HALF_SIZE from the centre (inside the corners, away from the
#     silhouette), located through the view file. Prints the probe's lines, then
#       contrast C centre P corners A B C D
#     with C = centre peak - brightest corner peak (luma of 8-bit sRGB codes, 0..255).
#   fig6_contrast.sh judge PER_VERTEX_CONTRAST PER_FRAGMENT_CONTRAST
#     Exit 0 when the per-fragment picture has a highlight inside (contrast >= MARGIN) and the
#     per-vertex one has none (contrast < MARGIN); says which failed otherwise.
#
# MARGIN = 40 luma levels. Measured on the CPU references of the default make_fig6_quad at MeshLab's
# default view (dry run): per fragment 173, per vertex 0 (the four corners' colours are equal,
# and the interpolation of equal colours is flat). 40 leaves room for MeshLab's lighting of its own
# mesh showing through nowhere (the decoration covers the quad) and for GL rasterisation differences.
set -euo pipefail
MARGIN=40

case "${1:-}" in
measure)
    probe="$2" view="$3" shot="$4" half="${5:-1}"
    c="$(awk -v h="$half" 'BEGIN { printf "%.6g", 0.7 * h }')"
    out="$("$probe" --view "$view" --screenshot "$shot" --radius 6 --point 0,0,0 \
        --point "-$c,-$c,0" --point "$c,-$c,0" --point "$c,$c,0" --point "-$c,$c,0")"
    echo "$out"
    awk '/^point /{ for (i = 1; i < NF; i++) if ($i == "peak") p[$2] = $(i + 1) }
         END { m = p[1]; for (k = 2; k <= 4; k++) if (p[k] > m) m = p[k];
               printf "contrast %.1f centre %.1f corners %.1f %.1f %.1f %.1f\n", p[0] - m, p[0], p[1], p[2], p[3], p[4] }' <<<"$out"
    ;;
judge)
    pv="$2" pf="$3"
    ok=0
    awk -v c="$pf" -v m="$MARGIN" 'BEGIN { exit !(c >= m) }' \
        || { echo "per fragment: the centre is not brighter than every corner by $MARGIN (contrast $pf): no highlight inside the quad" >&2; ok=1; }
    awk -v c="$pv" -v m="$MARGIN" 'BEGIN { exit !(c < m) }' \
        || { echo "per vertex: the centre is brighter than every corner by $MARGIN or more (contrast $pv): a highlight the vertices cannot make" >&2; ok=1; }
    exit "$ok"
    ;;
*)
    echo "usage: fig6_contrast.sh measure PROBE VIEW SHOT [HALF_SIZE] | judge PV_CONTRAST PF_CONTRAST" >&2
    exit 2
    ;;
esac
