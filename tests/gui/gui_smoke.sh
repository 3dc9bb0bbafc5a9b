#!/usr/bin/env bash
# GUI smoke test: starts Debian's real `meshlab` (private prefix) under Xvfb on a radiance file,
# waits for the window, takes a screenshot and checks that
#   - the mesh was drawn (enough pixels carry the mesh's vertex colour, which only our IO plugin
#     can have read from the .rply file), and
#   - MeshLab printed no plugin loading error for our plugins.
# Usage (from ctest): gui_smoke.sh INPUT.rply EXPECTED_R EXPECTED_G EXPECTED_B
source "$(dirname "$0")/../integration/lib.sh"
source "$(dirname "$0")/gui_lib.sh"
input="$1"; er="$2"; eg="$3"; eb="$4"

start_xvfb
start_meshlab smoke "$input"
sleep 2   # let the first frames render (llvmpipe)
kill -0 "$meshlab_pid" 2>/dev/null || { cat "$WORK/smoke.meshlab.log" >&2; fail "meshlab died after opening $input"; }
import -window root "$WORK/screenshot.png"
note "screenshot: $WORK/screenshot.png"

# Our plugins must load cleanly: MeshLab reports failures with the plugin file name.
if grep -iE "(radiance).*(fail|error|cannot|undefined symbol)|(fail|error|cannot).*(io_radiance|filter_radiance)" "$WORK/smoke.meshlab.log"; then
    fail "MeshLab reported a problem with our plugins (see $WORK/smoke.meshlab.log)"
fi

# Our IO plugin read the file: its log line reaches MeshLab's log (echoed on stdout as "LOG: ...").
grep -qE "Loaded [0-9]+ vertices with [A-Z]+[0-9]+ radiance functions" "$WORK/smoke.meshlab.log" \
    || { cat "$WORK/smoke.meshlab.log" >&2; fail "our IO plugin's log line is missing: the radiance data was not loaded"; }

python3 "$(dirname "$0")/count_colour_pixels.py" "$WORK/screenshot.png" "$er" "$eg" "$eb" 2000 \
    || fail "the mesh's colour is not on screen: the file was not loaded or not drawn"
note "ok"
