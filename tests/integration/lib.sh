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

# filter_script FILE FILTER_NAME [name=value]... : a one-filter script with every parameter the
# filter declares (meshlabserver 2020.09 aborts when one is missing), its defaults but for the values
# named (scripts/filter_script.sh: the list comes from the filter itself).
filter_script() {
    local file="$1" filter="$2"; shift 2
    bash "$RADIANCE_SOURCE_DIR/scripts/filter_script.sh" --out "$file" --filter "$filter" "$@"
}

# edit_mlx IN OUT NAME=VALUE...: a copy of the script IN with the named parameters' values replaced
# verbatim and unchecked (tests of what a hand-edited script may carry); a name IN lacks is an error.
edit_mlx() {
    python3 - "$@" <<'PY'
import sys, xml.etree.ElementTree as ET
source, target, *pairs = sys.argv[1:]
tree = ET.parse(source)
params = {p.get("name"): p for p in tree.iter("Param")}
for pair in pairs:
    name, value = pair.split("=", 1)
    params[name].set("value", value)
open(target, "w").write("<!DOCTYPE FilterScript>\n" + ET.tostring(tree.getroot(), encoding="unicode") + "\n")
PY
}

# create_radiance_mlx FILE BASIS(0=PB,1=SH) DEGREE REFLECTED(true|false) SPECULAR STRIPES [LIGHT_X LIGHT_Y LIGHT_Z
#                     [--filter OTHER name=value...]...]
# A script running "Create Radiance Data from Analytic Material": albedo (230, 60, 40) sRGB, white
# specular colour, directional light of irradiance 3, ambient 0.05, shininess 40, stripes along Y;
# then the other filters given after the light.
create_radiance_mlx() {
    local file="$1" basis="$2" degree="$3" reflected="$4" specular="$5" stripes="$6"
    local lx="${7:-0.5}" ly="${8:-1}" lz="${9:-1}"
    shift $(( $# < 9 ? $# : 9 ))
    filter_script "$file" "Radiance: Create Radiance Data from Analytic Material" \
        basis="$basis" degree="$degree" reflected="$reflected" albedo=230,60,40,255 specularColor=255,255,255,255 \
        specular="$specular" shininess=40 stripes="$stripes" stripeAxis=1 lightType=0 light="$lx,$ly,$lz" \
        lightIntensity=3 ambient=0.05 setColor=true "$@"
}

# fit_mlx FILE [BASIS(0=PB,1=SH)] [DEGREE] [REFLECTED] [QUALITY(0=count,1=residual)] [VALIDATION] [ROBUST]
#         [MODEL(0=automatic,1=per vertex,2=shared)]:
# a script running "Fit Radiance Functions from Rasters". VALIDATION and ROBUST default to false and
# MODEL to the per-vertex fit: these tests check that the least-squares fit reproduces the
# photographs it was fitted on (the per-vertex validation keeps the constant where a single
# photograph shows a highlight, and the shared fit, which the automatic choice may take, predicts
# unseen views at the cost of fitting the seen ones less closely; tests/python/test_pymeshlab_fit.py
# checks the defaults).
fit_mlx() {
    local file="$1" basis="${2:-0}" degree="${3:-4}" reflected="${4:-false}" quality="${5:-0}"
    local validation="${6:-false}" robust="${7:-false}" model="${8:-1}"
    filter_script "$file" "Radiance: Fit Radiance Functions from Rasters" \
        visibleOnly=false basis="$basis" degree="$degree" regularization=0.001 depthTolerance=0.003 \
        reflected="$reflected" quality="$quality" validation="$validation" robust="$robust" \
        exposureCompensation=true fitModel="$model" sharedGuard=3 lightDistance=0 heldOutEvery=0
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
