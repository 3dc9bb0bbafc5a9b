# Shared helpers of the integration tests (sourced). They drive Debian's real meshlabserver, from
# the private prefix of the build tree, under Xvfb (meshlabserver needs a display even in batch).
# Expects: MESHLAB_PREFIX, RADIANCE_BUILD_DIR, RADIANCE_SOURCE_DIR in the environment (set by ctest).
set -euo pipefail

: "${MESHLAB_PREFIX:?set by ctest}"
: "${RADIANCE_BUILD_DIR:?set by ctest}"
: "${RADIANCE_SOURCE_DIR:?set by ctest}"

TEST_NAME="$(basename "$0" .sh)"
WORK="$RADIANCE_BUILD_DIR/tests/integration-work/$TEST_NAME"
rm -rf "$WORK"
mkdir -p "$WORK/config"
# Private settings: MeshLab reads and writes its settings under XDG_CONFIG_HOME; never the user's.
export XDG_CONFIG_HOME="$WORK/config"
export HOME="$WORK"
PLY_READER="$RADIANCE_SOURCE_DIR/tests/integration/ply_reader.py"
MAKE_SCENE="$RADIANCE_BUILD_DIR/tools/make_scene"

fail() { echo "FAIL [$TEST_NAME]: $*" >&2; exit 1; }
note() { echo "[$TEST_NAME] $*"; }

# run_meshlabserver LOGFILE ARGS... : runs meshlabserver, its stdout+stderr in LOGFILE; returns its
# exit status; a crash (signal) is always a failure of the test.
run_meshlabserver() {
    local log="$1"; shift
    local status=0
    timeout 600 xvfb-run -a -s "-screen 0 1280x1024x24" \
        "$MESHLAB_PREFIX/bin/meshlabserver" "$@" >"$log" 2>&1 || status=$?
    if [ "$status" -ge 124 ]; then
        tail -n 30 "$log" >&2
        fail "meshlabserver crashed or timed out (status $status) with: $*"
    fi
    return "$status"
}

# write_mlx FILE FILTER_NAME PARAM_XML... : a one-filter script.
write_mlx() {
    local file="$1" filter="$2"; shift 2
    {
        echo '<!DOCTYPE FilterScript>'
        echo '<FilterScript>'
        echo " <filter name=\"$filter\">"
        for p in "$@"; do echo "  $p"; done
        echo ' </filter>'
        echo '</FilterScript>'
    } >"$file"
}
