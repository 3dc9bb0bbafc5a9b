#!/usr/bin/env bash
# The README's test command: sets everything up (apt packages, MeshLab 2020.09 and 2025.07 source
# headers, pymeshlab in build/python-venv, data, build, private MeshLab prefix), runs every test with
# ctest (unit tests of the cores, meshlabserver integration tests, GUI tests), installs the Python
# package from the repository into the venv (pip install: it compiles the pymeshlab plugins) and runs
# the pytest suite through the real pymeshlab, then the core tests once more under
# AddressSanitizer + UndefinedBehaviorSanitizer in a separate build.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
export BUILD_DIR
source "$REPO/scripts/compiler_cache.sh"
stage() { printf '[test] %s (%d s since the start)\n' "$*" "$SECONDS"; }

# The pytest suite tests the 2025 plugins that pip install compiles, and no test runs a benchmark
# program: the cmake build skips both (about a quarter of the compile time).
RADIANCE_PLUGINS_2025=OFF RADIANCE_BUILD_BENCH=OFF bash "$REPO/scripts/setup.sh"

stage "ctest (unit + integration + GUI)"
ctest --test-dir "$BUILD_DIR" --output-on-failure -j 2

VENV="$BUILD_DIR/python-venv"
stage "pip install of the Python package into $VENV (compiles the MeshLab 2025.07 plugins)"
"$VENV/bin/python" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps "$REPO"
"$VENV/bin/python" -c "import pymeshlab_radiance, sys; pymeshlab_radiance.load(); sys.stdout.write('[test] plugins loaded from %s\\n' % pymeshlab_radiance.plugin_dir())"
stage "pytest through pymeshlab 2025.7"
( cd "$REPO" && RADIANCE_BUILD_DIR="$BUILD_DIR" "$VENV/bin/python" -m pytest -q -p no:cacheprovider tests/python )

stage "core tests under AddressSanitizer + UndefinedBehaviorSanitizer"
SAN_DIR="${BUILD_DIR}-sanitize"
# -O1, as the sanitizers' authors advise (about half the compile time of -O2 with sanitizers), and line
# tables only (-g1): the reports keep file and line.
cmake -S "$REPO" -B "$SAN_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DRADIANCE_SANITIZE=ON \
      -DRADIANCE_BUILD_PLUGINS=OFF -DRADIANCE_BUILD_BENCH=OFF >/dev/null
cmake --build "$SAN_DIR" -j "$(nproc)" --target core_tests
# OpenMP's runtime keeps thread pools alive at exit; leak reports of libgomp are not ours.
ASAN_OPTIONS="detect_leaks=1:abort_on_error=0" \
UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
  ctest --test-dir "$SAN_DIR" --output-on-failure -j 2 -L unit
stage "done"
