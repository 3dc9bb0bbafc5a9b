#!/usr/bin/env bash
# GUI smoke test: starts Debian's real `meshlab` (private prefix) under Xvfb on a radiance file,
# waits for the window, takes a screenshot and checks that
#   - the mesh was drawn (enough pixels carry the mesh's vertex colour, which only our IO plugin
#     can have read from the .rply file), and
#   - MeshLab printed no plugin loading error for our plugins.
# Usage (from ctest): gui_smoke.sh INPUT.rply EXPECTED_R EXPECTED_G EXPECTED_B
source "$(dirname "$0")/../integration/lib.sh"
input="$1"; er="$2"; eg="$3"; eb="$4"

# Xvfb picks a free display itself (-displayfd) and writes its number once it accepts clients:
# no race with other X servers started by parallel tests.
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$WORK/display" >"$WORK/xvfb.log" 2>&1 &
xvfb_pid=$!
meshlab_pid=""
cleanup() {
    [ -n "$meshlab_pid" ] && kill "$meshlab_pid" 2>/dev/null || true
    kill "$xvfb_pid" 2>/dev/null || true
    wait 2>/dev/null || true
}
trap cleanup EXIT
for _ in $(seq 1 100); do [ -s "$WORK/display" ] && break; sleep 0.1; done
[ -s "$WORK/display" ] || { cat "$WORK/xvfb.log" >&2; fail "Xvfb did not start"; }
display=":$(head -n 1 "$WORK/display")"
export DISPLAY="$display"

"$MESHLAB_PREFIX/bin/meshlab" "$input" >"$WORK/meshlab.log" 2>&1 &
meshlab_pid=$!

window=""
for _ in $(seq 1 60); do
    window="$(xdotool search --onlyvisible --name 'MeshLab' 2>/dev/null | head -n 1 || true)"
    [ -n "$window" ] && break
    kill -0 "$meshlab_pid" 2>/dev/null || { cat "$WORK/meshlab.log" >&2; fail "meshlab exited early"; }
    sleep 0.5
done
[ -n "$window" ] || fail "no MeshLab window appeared within 30 s"
xdotool windowsize "$window" 1200 900 2>/dev/null || true
sleep 6   # let the first frames render (llvmpipe)
kill -0 "$meshlab_pid" 2>/dev/null || { cat "$WORK/meshlab.log" >&2; fail "meshlab died after opening $input"; }
import -window root "$WORK/screenshot.png"
note "screenshot: $WORK/screenshot.png"

# Our plugins must load cleanly: MeshLab reports failures with the plugin file name.
if grep -iE "(radiance).*(fail|error|cannot|undefined symbol)|(fail|error|cannot).*(io_radiance|filter_radiance)" "$WORK/meshlab.log"; then
    fail "MeshLab reported a problem with our plugins (see $WORK/meshlab.log)"
fi

# Our IO plugin read the file: its log line reaches MeshLab's log (echoed on stdout as "LOG: ...").
grep -qE "Loaded [0-9]+ vertices with [A-Z]+[0-9]+ radiance functions" "$WORK/meshlab.log" \
    || { cat "$WORK/meshlab.log" >&2; fail "our IO plugin's log line is missing: the radiance data was not loaded"; }

python3 "$(dirname "$0")/count_colour_pixels.py" "$WORK/screenshot.png" "$er" "$eg" "$eb" 2000 \
    || fail "the mesh's colour is not on screen: the file was not loaded or not drawn"
note "ok"
