#!/usr/bin/env bash
# Creates radiance data with the real meshlabserver on a generated sphere, saves it as .rply, and
# checks the file with an independent Python PLY reader against values computed in Python from the
# material (Lambert: the RF is a known constant per vertex). Then reloads the file in a second
# meshlabserver run and saves it again: every property must be bit-identical (lossless round trip).
# Both bases, plain and reflected storage, and a glossy material are covered.
source "$(dirname "$0")/lib.sh"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_radiance_ply.py"

"$MAKE_SCENE" sphere --level 3 -o "$WORK/sphere.ply"

run_case() {  # name basis(0/1) basisName degree reflected specular
    local name="$1" basis="$2" basis_name="$3" degree="$4" reflected="$5" specular="$6"
    create_radiance_mlx "$WORK/$name.mlx" "$basis" "$degree" "$reflected" "$specular" 0 0.5 1 1
    run_meshlabserver "$WORK/$name.create.log" -i "$WORK/sphere.ply" -o "$WORK/$name.rply" -m vc vn vq \
        -s "$WORK/$name.mlx" || { cat "$WORK/$name.create.log" >&2; fail "$name: create + save failed"; }
    [ -s "$WORK/$name.rply" ] || fail "$name: no file written"
    if [ "$specular" = "0" ]; then
        $CHECK lambert_sphere "$WORK/$name.rply" "$basis_name" "$degree" 0.5 1 1 3 0.05 230 60 40 || fail "$name: wrong radiance"
    else
        $CHECK directional "$WORK/$name.rply" || fail "$name: no directional variation"
    fi
    # Second run: load our file, save it again, compare bit for bit.
    run_meshlabserver "$WORK/$name.reload.log" -i "$WORK/$name.rply" -o "$WORK/$name.again.rply" -m vc vn vq \
        || { cat "$WORK/$name.reload.log" >&2; fail "$name: reload + save failed"; }
    $CHECK same "$WORK/$name.rply" "$WORK/$name.again.rply" || fail "$name: round trip not lossless"
    note "$name ok"
}

run_case pb4_lambert 0 PB 4 false 0
run_case sh6_lambert 1 SH 6 false 0
run_case pb6_glossy_reflected 0 PB 6 true 0.5
run_case sh8_glossy_reflected 1 SH 8 true 0.5
note "ok"
