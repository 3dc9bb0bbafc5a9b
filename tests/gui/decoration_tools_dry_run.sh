#!/usr/bin/env bash
# Dry run of the GUI decoration tests without MeshLab: checks the tools they use
# (compare_decoration_view, probe_decoration_view, make_fig6_quad) on "screenshots" made here by
# pasting the tools' own reference renderings into a larger screen at the position the view-file
# rules give, worked out here by hand (widget origin + viewport, the viewport's Y from the widget's
# bottom). A view file of MeshLab's default view is written by make_view_file.py (OpenGL matrices
# from the manual pages). What this proves: the crop and the row order of the comparison (a
# 1-pixel shift or an upside-down paste is caught), and that the Fig. 6 quad has a highlight in the
# middle per fragment and none per vertex under the very judgement gui_fig6_highlight.sh applies.
# What it cannot prove: that MeshLab's screen matches (the GUI tests do that).
# Usage: decoration_tools_dry_run.sh   (RADIANCE_BUILD_DIR, RADIANCE_SOURCE_DIR from ctest)
set -euo pipefail
: "${RADIANCE_BUILD_DIR:?set by ctest}"
: "${RADIANCE_SOURCE_DIR:?set by ctest}"
WORK="$RADIANCE_BUILD_DIR/tests/integration-work/decoration_tools_dry_run"
rm -rf "$WORK"; mkdir -p "$WORK"
TOOLS="$RADIANCE_BUILD_DIR/tools"
GUI="$RADIANCE_SOURCE_DIR/tests/gui"
fail() { echo "FAIL [dry run]: $*" >&2; exit 1; }
note() { echo "[dry run] $*"; }
# The real ImageMagick (paste, flip); /usr/bin first in case a stand-in shadows it.
CONVERT=/usr/bin/convert; [ -x "$CONVERT" ] || CONVERT=convert

# figure NAME OUTPUT: the value after NAME on the tool's "pixels N rmse X max Y p99 Z" line.
figure() { awk -v k="$1" '/^pixels /{for (i = 1; i < NF; i++) if ($i == k) print $(i + 1)}' <<<"$2"; }

# --- 1. crop and row order, on an asymmetric picture (glossy sphere lit from one side, turned) ---
"$TOOLS/make_scene" sphere --level 3 -o "$WORK/sphere.ply" >/dev/null
"$TOOLS/make_radiance_mesh" "$WORK/sphere.ply" -o "$WORK/sphere.rply" --basis PB4 >/dev/null
# Widget at (73, 91), 1000 x 700; viewport 900 x 600 at (20, 30) from the widget's bottom-left.
# Its top-left on the screen: x = 73 + 20 = 93, y = 91 + 700 - (30 + 600) = 161.
python3 "$GUI/make_view_file.py" "$WORK/view.txt" --bbox=-1,-1,-1,1,1,1 --widget-origin 73,91 \
    --widget-size 1000,700 --viewport 20,30,900,600 --yaw 25 --mode per-fragment --exposure 0.5 --tonemap reinhard
"$CONVERT" -size 1280x1024 xc:'rgb(60,60,80)' "$WORK/blank.png"
"$TOOLS/compare_decoration_view" --mesh "$WORK/sphere.rply" --view "$WORK/view.txt" --screenshot "$WORK/blank.png" \
    --out-reference "$WORK/reference.png" >/dev/null
paste_at() {  # paste_at PICTURE X Y OUT [extra convert options for the picture]
    local picture="$1" x="$2" y="$3" out="$4"; shift 4
    "$CONVERT" "$WORK/blank.png" \( "$picture" "$@" \) -geometry "+$x+$y" -composite -depth 8 "PNG24:$out"
}
compare() { "$TOOLS/compare_decoration_view" --mesh "$WORK/sphere.rply" --view "$WORK/view.txt" --screenshot "$1" "${@:2}"; }

paste_at "$WORK/reference.png" 93 161 "$WORK/shot-exact.png"
out="$(compare "$WORK/shot-exact.png" --out-diff "$WORK/diff-exact.png")" || fail "exact paste: $out"
note "exact paste:   $(grep '^pixels' <<<"$out")"
[ "$(figure max "$out")" = 0 ] || fail "the exact paste differs from the reference: the crop is wrong"
[ "$(figure pixels "$out")" -gt 20000 ] || fail "too few pixels compared on the exact paste"

paste_at "$WORK/reference.png" 93 162 "$WORK/shot-shifted.png"
out="$(compare "$WORK/shot-shifted.png")" || true
note "1 px lower:    $(grep '^pixels' <<<"$out")"
awk -v r="$(figure rmse "$out")" 'BEGIN { exit !(r > 0.3) }' || fail "a 1-pixel shift went unnoticed"

paste_at "$WORK/reference.png" 93 161 "$WORK/shot-flipped.png" -flip
out="$(compare "$WORK/shot-flipped.png")" || true
note "upside down:   $(grep '^pixels' <<<"$out")"
awk -v r="$(figure rmse "$out")" 'BEGIN { exit !(r > 5) }' || fail "an upside-down picture went unnoticed"

# Too few pixels: the mesh outside the comparison (everything excluded) must fail.
if compare "$WORK/shot-exact.png" --exclude 0,0,900,600 >/dev/null 2>&1; then
    fail "no pixel compared, yet the tool succeeded"
fi

# --- 2. Fig. 6 quad: the judgement of gui_fig6_highlight.sh on the references ---
"$TOOLS/make_fig6_quad" -o "$WORK/quad.rply" >/dev/null
python3 "$GUI/make_view_file.py" "$WORK/quad-view.txt" --bbox=-1,-1,0,1,1,0 --widget-origin 0,52 \
    --widget-size 1200,800 --viewport 0,0,1200,800
declare -A contrast
for mode in per-vertex per-fragment; do
    "$TOOLS/compare_decoration_view" --mesh "$WORK/quad.rply" --view "$WORK/quad-view.txt" --screenshot "$WORK/blank.png" \
        --shading "$mode" --out-reference "$WORK/quad-$mode.png" >/dev/null
    paste_at "$WORK/quad-$mode.png" 0 52 "$WORK/quad-shot-$mode.png"
    out="$(bash "$GUI/fig6_contrast.sh" measure "$TOOLS/probe_decoration_view" "$WORK/quad-view.txt" \
        "$WORK/quad-shot-$mode.png")" || fail "probe failed on the $mode picture: $out"
    note "$mode: $(grep '^contrast' <<<"$out")"
    contrast[$mode]="$(awk '/^contrast/{print $2}' <<<"$out")"
done
bash "$GUI/fig6_contrast.sh" judge "${contrast[per-vertex]}" "${contrast[per-fragment]}" \
    || fail "the Fig. 6 judgement fails on the CPU references"
note "ok"
