# shellcheck shell=bash
# Helpers of the GUI tests of the "Radiance Field" decoration (sourced after
# tests/integration/lib.sh): an Xvfb server, Debian's meshlab from the private prefix with private
# settings, the keys that show the decoration, and a screenshot taken while the view file the
# decoration writes (docs/decorate-radiance.md) is known to describe what is on screen.
# gui_smoke.sh uses the same Xvfb and meshlab start.

COMPARE_DECORATION_VIEW="$RADIANCE_BUILD_DIR/tools/compare_decoration_view"
PROBE_DECORATION_VIEW="$RADIANCE_BUILD_DIR/tools/probe_decoration_view"
MAKE_FIG6_QUAD="$RADIANCE_BUILD_DIR/tools/make_fig6_quad"
# MeshLab's info panel covers the bottom of the view (GLArea::displayInfo: 6 lines of 12 px text,
# about 90 px, translucent): never compared.
INFO_PANEL_ROWS=110

xvfb_pid=""
meshlab_pid=""
gui_cleanup() {
    if [ -n "$meshlab_pid" ]; then kill "$meshlab_pid" 2>/dev/null || true; fi
    if [ -n "$xvfb_pid" ]; then kill "$xvfb_pid" 2>/dev/null || true; fi
    wait 2>/dev/null || true
}
trap gui_cleanup EXIT

# start_xvfb: a private X server (it picks a free display itself and writes its number once it
# accepts clients: no race with parallel tests); exports DISPLAY. -noreset: by default the server
# resets when its last client leaves, and a meshlab started during the reset cannot connect
# ("could not connect to display"), seen between the shots of the multi-shot tests.
start_xvfb() {
    Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset 3>"$WORK/display" >"$WORK/xvfb.log" 2>&1 &
    xvfb_pid=$!
    for _ in $(seq 1 100); do [ -s "$WORK/display" ] && break; sleep 0.1; done
    [ -s "$WORK/display" ] || { cat "$WORK/xvfb.log" >&2; fail "Xvfb did not start"; }
    DISPLAY=":$(head -n 1 "$WORK/display")"
    export DISPLAY
}

# write_decoration_settings SHADING(0|1|2) EXPOSURE TONEMAP(0|1): a fresh private settings file with
# the decoration's keys, in the format MeshLab's QSettings writes them (docs/decorate-radiance.md):
# ':' escaped as %3A, the value the parameter's XML with \" and \n escapes. MeshLab adds every
# missing key with its default at start-up (MainWindow::loadMeshLabSettings). The enum labels are
# only shown in Tools > Options; the value is what the decoration reads.
write_decoration_settings() {
    local shading="$1" exposure="$2" tone="$3"
    mkdir -p "$XDG_CONFIG_HOME/VCG"
    cat >"$XDG_CONFIG_HOME/VCG/MeshLab_64bit_fp.conf" <<EOF
[General]
MeshLab%3A%3ADecoration%3A%3ARadianceShading="<!DOCTYPE MeshLabSettings>\n<Param type=\"RichEnum\" value=\"$shading\" name=\"MeshLab::Decoration::RadianceShading\" enum_cardinality=\"3\" enum_val0=\"Per vertex\" enum_val1=\"Per fragment\" enum_val2=\"PRT relighting\"/>\n"
MeshLab%3A%3ADecoration%3A%3ARadianceExposure="<!DOCTYPE MeshLabSettings>\n<Param type=\"RichFloat\" value=\"$exposure\" name=\"MeshLab::Decoration::RadianceExposure\"/>\n"
MeshLab%3A%3ADecoration%3A%3ARadianceToneMap="<!DOCTYPE MeshLabSettings>\n<Param type=\"RichEnum\" value=\"$tone\" name=\"MeshLab::Decoration::RadianceToneMap\" enum_cardinality=\"2\" enum_val0=\"Clamp\" enum_val1=\"Reinhard\"/>\n"
EOF
}

# start_meshlab NAME INPUT: meshlab on INPUT, the decoration's view file at $WORK/NAME.view.txt,
# stdout+stderr in $WORK/NAME.meshlab.log; waits for the window (sets `window`) and sizes it.
start_meshlab() {
    local name="$1" input="$2"
    rm -f "$WORK/$name.view.txt"
    RADIANCE_DECORATE_VIEW_FILE="$WORK/$name.view.txt" "$MESHLAB_PREFIX/bin/meshlab" "$input" \
        >"$WORK/$name.meshlab.log" 2>&1 &
    meshlab_pid=$!
    window=""
    for _ in $(seq 1 60); do
        window="$(xdotool search --onlyvisible --name 'MeshLab' 2>/dev/null | head -n 1 || true)"
        [ -n "$window" ] && break
        kill -0 "$meshlab_pid" 2>/dev/null || { cat "$WORK/$name.meshlab.log" >&2; fail "meshlab exited early"; }
        sleep 0.5
    done
    [ -n "$window" ] || fail "no MeshLab window appeared within 30 s"
    xdotool windowsize "$window" 1200 900 2>/dev/null || true
    sleep 4   # first frames (llvmpipe), the mesh loaded and the trackball reset
    kill -0 "$meshlab_pid" 2>/dev/null || { cat "$WORK/$name.meshlab.log" >&2; fail "meshlab died after opening $input"; }
}

stop_meshlab() {
    if [ -n "$meshlab_pid" ]; then
        kill "$meshlab_pid" 2>/dev/null || true
        wait "$meshlab_pid" 2>/dev/null || true
        meshlab_pid=""
    fi
}

# keys KEY...: keyboard input to the MeshLab window. There is no window manager under Xvfb:
# focus the window explicitly and keep the pointer over it (X's default focus follows the pointer).
keys() {
    xdotool windowfocus --sync "$window" 2>/dev/null || xdotool windowfocus "$window" || true
    xdotool mousemove --window "$window" 600 450
    for k in "$@"; do
        xdotool key --clearmodifiers "$k"
        sleep 0.5
    done
}

view_frame() { awk '$1 == "frame" { print $2 }' "$1" 2>/dev/null || true; }

# show_decoration NAME: hides the trackball (its rings are drawn over the mesh), resets the view
# (Ctrl+H: MeshLab's default front view in perspective; the keypad "Front" view would switch MeshLab
# to its orthographic projection, fov 5, which no pinhole camera describes), turns the decoration on
# (Ctrl+Alt+R), then waits until the view file exists and its frame number has not changed for 2 s,
# takes a screenshot of the whole screen ($WORK/NAME.png) and keeps the view file of that moment
# ($WORK/NAME.view-at-shot.txt); retried when a frame was drawn during the capture.
show_decoration() {
    local name="$1" file="$WORK/$1.view.txt"
    keys shift+h ctrl+h ctrl+alt+r
    local attempt
    for attempt in 1 2 3; do
        local start=$SECONDS since=$SECONDS last="" frame
        while :; do
            kill -0 "$meshlab_pid" 2>/dev/null || { tail -n 30 "$WORK/$name.meshlab.log" >&2; fail "meshlab died"; }
            frame="$(view_frame "$file")"
            if [ -n "$frame" ] && [ "$frame" = "$last" ]; then
                [ $((SECONDS - since)) -ge 2 ] && break
            else
                last="$frame"
                since=$SECONDS
            fi
            if [ $((SECONDS - start)) -gt 60 ]; then
                tail -n 30 "$WORK/$name.meshlab.log" >&2
                if [ -e "$file" ]; then fail "the view file $file never settled (last frame '$last')"; fi
                fail "the decoration wrote no view file within 60 s: not loaded, not turned on (Ctrl+Alt+R), or RADIANCE_DECORATE_VIEW_FILE ignored"
            fi
            sleep 0.25
        done
        cp "$file" "$WORK/$name.view-at-shot.txt"
        import -window root "$WORK/$name.png"
        if [ "$(view_frame "$file")" = "$(view_frame "$WORK/$name.view-at-shot.txt")" ]; then
            note "$name: screenshot at frame $frame ($WORK/$name.png)"
            return 0
        fi
        note "$name: a frame was drawn during the screenshot (attempt $attempt), again"
    done
    fail "MeshLab kept redrawing: no screenshot matches a view file"
}

# check_decoration_log NAME: no GL error from our plugin, and its start line is there.
check_decoration_log() {
    local log="$WORK/$1.meshlab.log"
    if grep -n "GL error" "$log"; then fail "the decoration reported a GL error (see $log)"; fi
    if grep -iE "(radiance).*(fail|cannot|undefined symbol)|decorate_radiance.*(error|fail)" "$log"; then
        fail "MeshLab reported a problem with our plugins (see $log)"
    fi
    grep -qiE "Radiance Field.*(shading|uploaded|started)" "$log" \
        || { tail -n 40 "$log" >&2; fail "no 'Radiance Field' start line in MeshLab's log: the decoration did not start"; }
}

# check_view_mode NAME EXPECTED: the decoration used the shading the settings asked for.
check_view_mode() {
    local mode
    mode="$(awk '$1 == "mode" { print $2 }' "$WORK/$1.view-at-shot.txt")"
    [ "$mode" = "$2" ] || fail "the decoration drew in mode '$mode', the settings asked for '$2': settings not read?"
}

# bake_armadillo SIZE: the armadillo scan decimated to 1000 faces by MeshLab and "Bake Normal Map"
# (SIZE^2, object space, LEAN) from the full scan, through meshlabserver: $WORK/armadillo_baked.ply
# with wedge UVs and normals, its maps $WORK/armadillo_normal.png and _lean.exr.
bake_armadillo() {
    local size="$1"
    local scan="${RADIANCE_DATA_CACHE:-$RADIANCE_SOURCE_DIR/data-cache}/meshes/armadillo.off"
    [ -s "$scan" ] || fail "no $scan (scripts/setup.sh fetches it)"
    {
        echo '<!DOCTYPE FilterScript>'
        echo '<FilterScript>'
        bash "$RADIANCE_SOURCE_DIR/scripts/meshlab_decimation_filter.sh" 1000 true
        bash "$RADIANCE_SOURCE_DIR/scripts/bake_normal_map_filter.sh" 0 "$size" 0 0 true true "$WORK/armadillo_normal.png"
        echo '</FilterScript>'
    } >"$WORK/simplify.mlx"
    run_meshlabserver "$WORK/prepare.log" -i "$scan" -i "$scan" -s "$WORK/simplify.mlx" -o "$WORK/armadillo_baked.ply" -m wt vn \
        || { cat "$WORK/prepare.log" >&2; fail "simplification + bake failed"; }
}
