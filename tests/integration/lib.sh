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
    # 255 is meshlabserver's own "failed" (exit -1); 124 is timeout's; 129..254 are signals (crashes).
    if [ "$status" -eq 124 ] || { [ "$status" -gt 128 ] && [ "$status" -lt 255 ]; }; then
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

# create_radiance_mlx FILE BASIS(0=PB,1=SH) DEGREE REFLECTED(true|false) SPECULAR STRIPES [LIGHT_X LIGHT_Y LIGHT_Z]
# A script running "Create Radiance Data from Analytic Material" with every parameter listed
# (meshlabserver 2020.09 aborts when one is missing). Albedo (230, 60, 40) sRGB, directional light
# of irradiance 3, ambient 0.05, shininess 40.
create_radiance_mlx() {
    local file="$1" basis="$2" degree="$3" reflected="$4" specular="$5" stripes="$6"
    local lx="${7:-0.5}" ly="${8:-1}" lz="${9:-1}"
    write_mlx "$file" "Radiance: Create Radiance Data from Analytic Material" \
        "<Param type=\"RichEnum\" name=\"basis\" value=\"$basis\" enum_cardinality=\"2\" enum_val0=\"PB\" enum_val1=\"SH\"/>" \
        "<Param type=\"RichInt\" name=\"degree\" value=\"$degree\"/>" \
        "<Param type=\"RichBool\" name=\"reflected\" value=\"$reflected\"/>" \
        '<Param type="RichColor" name="albedo" r="230" g="60" b="40" a="255"/>' \
        '<Param type="RichColor" name="specularColor" r="255" g="255" b="255" a="255"/>' \
        "<Param type=\"RichFloat\" name=\"specular\" value=\"$specular\"/>" \
        '<Param type="RichFloat" name="shininess" value="40"/>' \
        "<Param type=\"RichInt\" name=\"stripes\" value=\"$stripes\"/>" \
        '<Param type="RichEnum" name="stripeAxis" value="1" enum_cardinality="3" enum_val0="X" enum_val1="Y" enum_val2="Z"/>' \
        '<Param type="RichEnum" name="lightType" value="0" enum_cardinality="2" enum_val0="Directional" enum_val1="Point"/>' \
        "<Param type=\"RichPoint3f\" name=\"light\" x=\"$lx\" y=\"$ly\" z=\"$lz\"/>" \
        '<Param type="RichFloat" name="lightIntensity" value="3"/>' \
        '<Param type="RichFloat" name="ambient" value="0.05"/>' \
        '<Param type="RichBool" name="setColor" value="true"/>'
}

# fit_mlx FILE [BASIS(0=PB,1=SH)] [DEGREE] [REFLECTED] [QUALITY(0=count,1=residual)] [VALIDATION] [ROBUST]:
# a script running "Fit Radiance Functions from Rasters" with every parameter listed. VALIDATION and
# ROBUST default to false: these tests check that the least-squares fit reproduces the photographs
# it was fitted on (the per-vertex validation keeps the constant where a single photograph shows a
# highlight; tests/python/test_pymeshlab_fit.py checks the defaults).
fit_mlx() {
    local file="$1" basis="${2:-0}" degree="${3:-4}" reflected="${4:-false}" quality="${5:-0}"
    local validation="${6:-false}" robust="${7:-false}"
    write_mlx "$file" "Radiance: Fit Radiance Functions from Rasters" \
        '<Param type="RichBool" name="visibleOnly" value="false"/>' \
        "<Param type=\"RichEnum\" name=\"basis\" value=\"$basis\" enum_cardinality=\"2\" enum_val0=\"PB\" enum_val1=\"SH\"/>" \
        "<Param type=\"RichInt\" name=\"degree\" value=\"$degree\"/>" \
        '<Param type="RichFloat" name="regularization" value="0.001"/>' \
        '<Param type="RichAbsPerc" name="depthTolerance" value="0.003" min="0" max="10"/>' \
        '<Param type="RichFloat" name="grazingAngle" value="80"/>' \
        '<Param type="RichInt" name="borderMargin" value="2"/>' \
        '<Param type="RichInt" name="minSamples" value="3"/>' \
        "<Param type=\"RichBool\" name=\"reflected\" value=\"$reflected\"/>" \
        "<Param type=\"RichEnum\" name=\"quality\" value=\"$quality\" enum_cardinality=\"2\" enum_val0=\"count\" enum_val1=\"residual\"/>" \
        '<Param type="RichBool" name="setColor" value="true"/>' \
        "<Param type=\"RichBool\" name=\"validation\" value=\"$validation\"/>" \
        "<Param type=\"RichBool\" name=\"robust\" value=\"$robust\"/>" \
        '<Param type="RichBool" name="exposureCompensation" value="true"/>' \
        '<Param type="RichEnum" name="fitModel" value="0" enum_cardinality="3" enum_val0="automatic" enum_val1="pervertex" enum_val2="shared"/>' \
        '<Param type="RichInt" name="heldOutEvery" value="0"/>'
}

VIRTUAL_ACQUISITION="$RADIANCE_BUILD_DIR/tools/virtual_acquisition"

# expect_refusal NAME MESSAGE MESH MLX: running MLX on MESH fails with MESSAGE in the log (no crash),
# and the layer, saved after the refusal, is identical to the mesh saved without the script.
expect_refusal() {
    local name="$1" message="$2" mesh="$3" mlx="$4"
    local ext="${mesh##*.}"
    run_meshlabserver "$WORK/$name.ref.log" -i "$mesh" -o "$WORK/$name.ref.$ext" || fail "$name: cannot save the reference"
    run_meshlabserver "$WORK/$name.log" -i "$mesh" -s "$mlx" -o "$WORK/$name.out.$ext" || true
    grep -qF "$message" "$WORK/$name.log" || { cat "$WORK/$name.log" >&2; fail "$name: no message '$message'"; }
    if [ -e "$WORK/$name.out.$ext" ]; then
        python3 "$RADIANCE_SOURCE_DIR/tests/integration/check_radiance_ply.py" same "$WORK/$name.ref.$ext" \
            "$WORK/$name.out.$ext" || fail "$name: layer changed by a refused filter"
    fi
    note "$name refused: $(grep -F "$message" "$WORK/$name.log" | head -n 1)"
}
