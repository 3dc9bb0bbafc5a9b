#!/usr/bin/env bash
# `meshlabserver -d` on the private prefix lists our filters with their help text, and Debian's
# own filters are still there (the prefix links the system plugins too).
source "$(dirname "$0")/lib.sh"

run_meshlabserver "$WORK/server.log" -d "$WORK/dump.txt" || true
[ -s "$WORK/dump.txt" ] || { cat "$WORK/server.log" >&2; fail "meshlabserver -d wrote no dump"; }

for name in "Radiance: Create Radiance Data from Analytic Material" \
            "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color" \
            "Extract Level of Detail (POP Buffer)" \
            "Out-of-Core Simplification and Normal Map" \
            "Compute Irradiance Vector Grid" \
            "Import Cameras as Raster Layers" \
            "Radiance: Export Radiance Functions as glTF (.glb)" \
            "Radiance: Transfer Radiance from Gaussian Splats"; do
    grep -qF "$name" "$WORK/dump.txt" || fail "filter '$name' missing from meshlabserver -d"
done
# Help text, with the paper it implements.
grep -qF "Simplification of meshes with digitized radiance" "$WORK/dump.txt" || fail "help text does not cite Vanhoey et al. 2015"
grep -qF "hemispherical polynomials" "$WORK/dump.txt" || fail "help text of the create filter missing"
grep -qF "Rapid Progressive Clustering by Geometry Quantization" "$WORK/dump.txt" || fail "help text does not cite Limper et al. 2013"
grep -qF "Out-of-Core Simplification of Large Polygonal Models" "$WORK/dump.txt" || fail "help text does not cite Lindstrom 2000"
grep -qF "The Irradiance Jacobian for Partially Occluded Polyhedral Sources" "$WORK/dump.txt" || fail "help text of the irradiance grid does not cite Arvo 1994"
grep -qF "COLMAP</b> sparse model" "$WORK/dump.txt" || fail "help text of the camera import missing"
# Parameters are listed with their descriptions.
grep -qF "Store reflected functions" "$WORK/dump.txt" || fail "parameter descriptions missing"
# The system plugins are loaded too.
grep -qF "Simplification: Quadric Edge Collapse Decimation" "$WORK/dump.txt" || fail "Debian's filters missing: prefix broken"
# No loading problem reported for our plugins.
if grep -iE "(io_radiance|filter_radiance|filter_level_of_detail|filter_irradiance_grid|filter_out_of_core|filter_normal_bake|filter_prt_subdivide).*(fail|error|undefined)" "$WORK/server.log"; then
    fail "meshlabserver reported a problem loading our plugins"
fi
note "ok"
