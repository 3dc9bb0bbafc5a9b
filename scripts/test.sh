#!/usr/bin/env bash
# The README's test command: sets everything up (apt packages, MeshLab 2020.09 and 2025.07 source
# headers, pymeshlab in build/python-venv, data, build, private MeshLab prefix), runs every test with
# ctest (unit tests of the cores, meshlabserver integration tests, GUI tests), builds the binary wheel
# (scripts/build_wheel.sh: it compiles the pymeshlab plugins), installs it with --no-deps into a fresh
# venv beside pymeshlab and runs the pytest suite there through the real pymeshlab, then the core tests once more under
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

VENV="$BUILD_DIR/wheel-venv"
stage "binary wheel (compiles the MeshLab 2025.07 plugins), installed with --no-deps into a fresh $VENV beside pymeshlab"
# The fresh venv (pymeshlab and the test extras) fills while the wheel compiles.
WHEEL_VENV_EXTRAS="pytest>=7 pygltflib>=1.15 pycolmap dask[distributed]>=2023.1 matplotlib>=3.5" \
  bash "$REPO/tests/wheel/check_wheel.sh" --prepare "$VENV" > "$BUILD_DIR/wheel-venv.log" 2>&1 & PREPARE=$!
WHEEL="$(bash "$REPO/scripts/build_wheel.sh")"
wait "$PREPARE" || { cat "$BUILD_DIR/wheel-venv.log" >&2; exit 1; }
bash "$REPO/tests/wheel/check_wheel.sh" "$WHEEL" "$VENV"
stage "pytest through pymeshlab 2025.7, against the installed wheel"
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
