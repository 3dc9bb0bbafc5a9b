#!/usr/bin/env bash
# write_prt_mlx.sh OUT.mlx STEP [STEP...]: a meshlabserver script running the PRT filters in order
# (each filter's defaults for what a step does not set). Steps:
#   transfer:ORDER:RAYS[:OCCLUDERS(0 mesh|1 visible layers)[:ALBEDO(true|false)]]
#   adaptive:FACTOR[:MEASURE(0 eq.2|1 eq.3|2 eq.4|3 probed (default)|4 probed absolute)[:ALPHA[:THRESHOLD[:BUDGET]]]]
#   uniform:FACTOR[:BUDGET]
#   relight-dir:X:Y:Z[:INTENSITY]
#   relight-env:FILE[:ROTATION_DEGREES[:UP(0 +X|1 +Y|2 +Z)]]   (the map at intensity 1)
# FACTOR: budget as a multiple of the face count (0: use BUDGET, an absolute face count).
set -euo pipefail
out="$1"; shift
filters=()
for step in "$@"; do
    IFS=: read -r kind a b c d e f <<<"$step"
    case "$kind" in
    transfer)
        filters+=(--filter "Radiance: Compute PRT Transfer" order="${a:-6}" rays="${b:-256}" occluders="${c:-0}"
                  albedo="${d:-false}") ;;
    adaptive)
        filters+=(--filter "Radiance: Adaptive PRT Subdivision" budget="${e:-0}" budgetFactor="${a:-4}"
                  measure="${b:-3}" alpha="${c:-4}" threshold="${d:-0}") ;;
    uniform)
        filters+=(--filter "Radiance: Uniform PRT Subdivision" budget="${b:-0}" budgetFactor="${a:-4}") ;;
    relight-dir)
        filters+=(--filter "Radiance: PRT Relighting as Vertex Color" lighting=1 lightDirection="$a,$b,$c"
                  lightIntensity="${d:-3}") ;;
    relight-env)
        filters+=(--filter "Radiance: PRT Relighting as Vertex Color" lighting=0 environmentMap="$a"
                  rotation="${b:-0}" upAxis="${c:-2}" lightIntensity=1) ;;
    *) echo "write_prt_mlx.sh: unknown step '$step'" >&2; exit 2 ;;
    esac
done
bash "$(dirname "$0")/filter_script.sh" --out "$out" "${filters[@]}"
