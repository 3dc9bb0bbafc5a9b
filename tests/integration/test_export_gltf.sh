#!/usr/bin/env bash
# 'Radiance: Export Radiance Functions as glTF (.glb)' with the real meshlabserver (MeshLab 2020.09):
# radiance created on a sphere, saved as .rply and exported as .glb in the same run; the .glb checked
# against the .rply with a standard-library reader (check_radiance_glb.py). Then the refusals: a mesh
# without radiance and a folder that does not exist, each with its message and no file written.
source "$(dirname "$0")/lib.sh"

"$MAKE_SCENE" sphere --level 2 -o "$WORK/sphere.ply"
export_mlx() {  # FILE OUTPUT
    filter_script "$1" "Radiance: Export Radiance Functions as glTF (.glb)" \
        "outputFile=$2"
}

for case in "pb3:0:3:false" "sh3_reflected:1:3:true"; do
    IFS=: read -r name basis degree reflected <<<"$case"
    create_radiance_mlx "$WORK/$name.create.mlx" "$basis" "$degree" "$reflected" 0.5 0
    export_mlx "$WORK/$name.export.mlx" "$WORK/$name.glb"
    # One script: create, then export (the layer is saved with -o after both filters).
    { head -n -1 "$WORK/$name.create.mlx"; tail -n +3 "$WORK/$name.export.mlx"; } >"$WORK/$name.mlx"
    run_meshlabserver "$WORK/$name.log" -i "$WORK/sphere.ply" -o "$WORK/$name.rply" -m vc vn -s "$WORK/$name.mlx" \
        || { cat "$WORK/$name.log" >&2; fail "$name: create + export failed"; }
    python3 "$RADIANCE_SOURCE_DIR/tests/integration/check_radiance_glb.py" "$WORK/$name.glb" "$WORK/$name.rply" \
        || fail "$name: the .glb does not hold the layer's radiance"
    note "$name ok"
done

export_mlx "$WORK/none.mlx" "$WORK/none.glb"
run_meshlabserver "$WORK/none.log" -i "$WORK/sphere.ply" -s "$WORK/none.mlx" && fail "export without radiance accepted"
grep -q "no radiance data" "$WORK/none.log" || { cat "$WORK/none.log" >&2; fail "no reason given for the refusal"; }
export_mlx "$WORK/missing.export.mlx" "$WORK/missing/x.glb"
create_radiance_mlx "$WORK/missing.create.mlx" 1 2 false 0 0
{ head -n -1 "$WORK/missing.create.mlx"; tail -n +3 "$WORK/missing.export.mlx"; } >"$WORK/missing.mlx"
run_meshlabserver "$WORK/missing.log" -i "$WORK/sphere.ply" -s "$WORK/missing.mlx" && fail "export into a missing folder accepted"
grep -q "does not exist" "$WORK/missing.log" || { cat "$WORK/missing.log" >&2; fail "no reason given for the refusal"; }
[ ! -e "$WORK/none.glb" ] && [ ! -e "$WORK/missing" ] || fail "a refused export wrote a file"
note "ok"
