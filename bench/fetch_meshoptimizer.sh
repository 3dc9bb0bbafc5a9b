#!/usr/bin/env bash
# Unpacks meshoptimizer's sources, as the package registry distributes them, into the build tree for
# bench_vs_meshoptimizer (never committed). The Python package's source distribution bundles the
# C++ library in src/; `pip download` reads this machine's index configuration.
#   bench/fetch_meshoptimizer.sh [BUILD_DIR (build)] [VERSION (0.2.30a0)]
# then: cmake -S . -B BUILD_DIR -DRADIANCE_BENCH_MESHOPTIMIZER=ON && cmake --build BUILD_DIR --target bench_vs_meshoptimizer
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="$(mkdir -p "${1:-$REPO/build}" && cd "${1:-$REPO/build}" && pwd)"
VERSION="${2:-0.2.30a0}"
DEST="$BUILD_DIR/meshoptimizer-src"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
# Source distribution only (no wheel); without build isolation pip only needs setuptools to read
# the metadata, instead of installing build dependencies.
python3 -m pip download --quiet --no-deps --no-binary :all: --no-build-isolation -d "$WORK" "meshoptimizer==$VERSION"
archive="$(ls "$WORK"/meshoptimizer-*.tar.gz)"
rm -rf "$DEST"
mkdir -p "$DEST"
tar -xzf "$archive" -C "$DEST" --strip-components=1
grep -m1 "define MESHOPTIMIZER_VERSION" "$DEST/src/meshoptimizer.h"
echo "meshoptimizer sources in $DEST/src ($(basename "$archive"))"
