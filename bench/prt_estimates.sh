#!/usr/bin/env bash
# The PRT error estimates side by side (docs/prt-subdivision.md, "Figures: precomputed radiance transfer"): adaptive vs uniform
# subdivision at equal triangle count on the column of Křivánek et al. 2004 and three real scans on a
# plane, for each estimate (probed relative = the default, eq. 4, eq. 3, eq. 2, probed absolute),
# relative (Weber) and absolute error. Run from the repository after the build and
# samples/fetch_data.sh; about 6 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
EVAL="${BUILD_DIR:-build}/tools/evaluate_prt"
DATA="${RADIANCE_DATA_CACHE:-data-cache}"
HDR=(--hdr "$DATA/hdr/city.exr" --hdr "$DATA/hdr/courtyard.exr" --hdr "$DATA/hdr/forest.exr" --hdr "$DATA/hdr/studio.exr")
for measure in probed 4 3 2 probed-absolute; do
  for scene in column bunny00 armadillo ChineseDragon-10kv; do
    echo "=== $scene, estimate $measure"
    if [ "$scene" = column ]; then
      args=(--scene column)
    else
      args=(--mesh "$DATA/meshes/$scene.off" --up y --simplify-to 2000)
    fi
    "$EVAL" "${args[@]}" --levels 2 "${HDR[@]}" --measure "$measure" | grep -E "adaptive:|lower|absolute error"
  done
done
