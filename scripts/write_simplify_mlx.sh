#!/usr/bin/env bash
# write_simplify_mlx.sh OUT.mlx PERCENTAGE [METRIC] [LOD_LEVELS] [PROGRESSIVE_FILE] [COLLAPSE]: a
# meshlabserver script running "Radiance: Radiance-Aware Simplification". PERCENTAGE: target as a
# fraction of the faces (e.g. 0.1); METRIC: 0 radiance eq. 7 (default here), 1 light field 2010,
# 2 colour QEM, 3 geometry, 4 radiance quadric (the filter's default); LOD_LEVELS e.g. "0.5 0.25";
# PROGRESSIVE_FILE an absolute .rpm path or empty; COLLAPSE 0 half-edge (default here), 1 full.
# The other parameters take the filter's defaults.
set -euo pipefail
out="$1"; percentage="$2"; metric="${3:-0}"; lods="${4:-}"; progressive="${5:-}"; collapse="${6:-0}"
bash "$(dirname "$0")/filter_script.sh" --out "$out" --filter "Radiance: Radiance-Aware Simplification" \
    metric="$metric" collapse="$collapse" targetFaces=0 targetPercentage="$percentage" lodLevels="$lods" \
    progressiveFile="$progressive"
