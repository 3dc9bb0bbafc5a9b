#!/usr/bin/env bash
# filter_script.sh ARGS...: writes a MeshLab 2020.09 filter script from the filters' own parameter
# lists (tools/meshlab2020/write_filter_script.cpp): every parameter a filter declares, with its
# default, and the values named on the command line, e.g.
#   filter_script.sh --out OUT.mlx --filter "Radiance: Radiance-Aware Simplification" targetPercentage=0.1
# Reads the program and the plugins (ours and MeshLab's own) from the build folder
# (RADIANCE_BUILD_DIR, else BUILD_DIR, else build/ of the repository).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${RADIANCE_BUILD_DIR:-${BUILD_DIR:-$repo/build}}"
program="$build/tools/meshlab2020/radiance_filter_script"
plugins=("$build"/meshlab-prefix/lib/*/meshlab/plugins)
if [ ! -x "$program" ] || [ ! -d "${plugins[0]}" ]; then
    echo "filter_script.sh: $program or the MeshLab prefix of $build is missing: build the project first (scripts/setup.sh)" >&2
    exit 2
fi
# Qt's start-up notes (no XDG runtime folder) are not the script's business.
exec "$program" --plugins "${plugins[0]}" "$@" 2> >(grep -v '^QStandardPaths:' >&2)
