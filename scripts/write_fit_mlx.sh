#!/usr/bin/env bash
# write_fit_mlx.sh OUT.mlx [DEPTH_TOLERANCE] [DEGREE]: a meshlabserver script running "Radiance: Fit
# Radiance Functions from Rasters" (PB basis, the filter's defaults otherwise). DEPTH_TOLERANCE in
# scene units (default 0.0002), DEGREE default 4.
set -euo pipefail
out="$1"; tolerance="${2:-0.0002}"; degree="${3:-4}"
bash "$(dirname "$0")/filter_script.sh" --out "$out" --filter "Radiance: Fit Radiance Functions from Rasters" \
    basis=0 degree="$degree" depthTolerance="$tolerance"
