#!/usr/bin/env bash
# Prints the <filter> element of MeshLab's "Simplification: Quadric Edge Collapse Decimation" (every
# parameter, from MeshLab's own list), for embedding in .mlx scripts (the baseline and the
# simplified targets of the normal-map bakes).
# Usage: meshlab_decimation_filter.sh TARGET_FACES [PRESERVE_TOPOLOGY(true|false, default false)]
#                                     [PRESERVE_NORMAL(true|false, default true)]
set -euo pipefail
faces="${1:?usage: meshlab_decimation_filter.sh TARGET_FACES [PRESERVE_TOPOLOGY]}"
topology="${2:-false}"
normal="${3:-true}"
bash "$(dirname "$0")/filter_script.sh" --elements-only --out - --filter "Simplification: Quadric Edge Collapse Decimation" \
    TargetFaceNum="$faces" TargetPerc=0 PreserveNormal="$normal" PreserveTopology="$topology" OptimalPlacement=true \
    AutoClean=true
