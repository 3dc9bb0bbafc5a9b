#!/usr/bin/env bash
# The binary wheel as a pymeshlab user gets it: a fresh virtual environment (python3 -m venv) with
# only pymeshlab 2025.7.post1, numpy and tqdm, the wheel installed with --no-deps; then, outside the
# repository and with LD_LIBRARY_PATH unset, installed_wheel_check.py (where every library the plugins
# load comes from, ldd, all filters listed, two run, the result read with rply) and the console script
# (`meshlab-radiance --help`, `meshlab-radiance filters --ours`).
#
# Usage: tests/wheel/check_wheel.sh WHEEL [VENV]
#        tests/wheel/check_wheel.sh --prepare VENV   (only the fresh venv, without the wheel)
#   VENV (default: a temporary folder, removed at the end) is made afresh, unless `--prepare` made it
#   just before (scripts/test.sh fills it while the wheel compiles); when given it is kept, and
#   WHEEL_VENV_EXTRAS (pip requirements, space-separated) are installed in the same pip call, so that
#   scripts/test.sh runs the pytest suite in it. Prints the pip install time of the wheel.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
log() { printf '[wheel-check] %s\n' "$*"; }
pip_install() {  # PYTHON ARGS...: quiet pip, its output shown only when it fails
  local python="$1" out; shift
  out="$(mktemp)"
  "$python" -m pip install -q --disable-pip-version-check "$@" > "$out" 2>&1 ||
    { grep -v "is ignored" "$out" >&2; rm -f "$out"; log "FAILED: pip install $*" >&2; exit 1; }
  rm -f "$out"
}

fresh_venv() {  # VENV: python3 -m venv, pymeshlab, numpy, tqdm and the extras; marked as fresh
  rm -rf "$1"
  python3 -m venv "$1"
  local extras
  read -r -a extras <<< "${WHEEL_VENV_EXTRAS:-}"  # split on spaces, never globbed (dask[distributed])
  pip_install "$1/bin/python" 'pymeshlab==2025.7.post1' 'numpy>=1.21' 'tqdm>=4.60' "${extras[@]}"
  touch "$1/.fresh-for-check-wheel"
}

if [ "${1:-}" = "--prepare" ]; then
  fresh_venv "${2:?usage: check_wheel.sh --prepare VENV}"
  exit 0
fi
WHEEL="$(realpath "${1:?usage: check_wheel.sh WHEEL [VENV]}")"
VENV="${2:-}"
if [ -z "$VENV" ]; then
  VENV="$(mktemp -d)/venv"
  trap 'rm -rf "$(dirname "$VENV")"' EXIT
fi
if [ -f "$VENV/.fresh-for-check-wheel" ]; then
  rm "$VENV/.fresh-for-check-wheel"  # used once: a later check without --prepare starts afresh
else
  fresh_venv "$VENV"
  rm "$VENV/.fresh-for-check-wheel"
fi
start=$EPOCHREALTIME
pip_install "$VENV/bin/python" --no-deps "$WHEEL"
seconds="$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }')"
log "pip install --no-deps of $(basename "$WHEEL") ($(du -h "$WHEEL" | cut -f1)): $seconds s"

# Outside the repository (nothing importable from it), no library path, no plugin folder override.
cd "$(mktemp -d)"
CLEAN=(env -u LD_LIBRARY_PATH -u PYTHONPATH -u PYMESHLAB_RADIANCE_PLUGIN_DIR)
"${CLEAN[@]}" "$VENV/bin/python" "$HERE/installed_wheel_check.py"
"${CLEAN[@]}" "$VENV/bin/meshlab-radiance" --help > help.txt
for command in fit simplify bake info filters batch import-cameras; do
  grep -q "$command" help.txt || { log "FAILED: meshlab-radiance --help does not list '$command'" >&2; exit 1; }
done
"${CLEAN[@]}" "$VENV/bin/meshlab-radiance" filters --ours > ours.txt
"${CLEAN[@]}" "$VENV/bin/python" -c "
import sys, pymeshlab_radiance
listed = open('ours.txt').read().split()
sys.exit(0 if sorted(listed) == sorted(pymeshlab_radiance.filter_names()) else 'meshlab-radiance filters --ours listed %s' % listed)"
log "meshlab-radiance --help lists every subcommand; 'filters --ours' lists our $(wc -l < ours.txt) filters"
rm -rf "$PWD"
log "OK"
