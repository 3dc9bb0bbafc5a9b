#!/bin/sh
# Configures and builds the libFuzzer harnesses (bench/fuzz/CMakeLists.txt) into $FUZZ_BUILD_DIR
# (default build-fuzz/): clang, -O1 -g, AddressSanitizer + UndefinedBehaviorSanitizer, the cores
# compiled once on every core and linked by every harness. Incremental: a second run rebuilds only what
# changed. Usage: bench/fuzz/build.sh TARGET... (on Debian: apt-get install clang libomp-dev).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${FUZZ_BUILD_DIR:-$root/build-fuzz}
if [ ! -f "$out/CMakeCache.txt" ]; then
  CC=${CC_FUZZ:-clang} CXX=${CXX_FUZZ:-clang++} cmake -S "$root" -B "$out" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" -DRADIANCE_FUZZ=ON -DRADIANCE_BUILD_PLUGINS=OFF \
    -DRADIANCE_BUILD_BENCH=OFF -DRADIANCE_BUILD_TOOLS=OFF -DRADIANCE_BUILD_TESTS=OFF >/dev/null
fi
cmake --build "$out" -j "$(nproc)" --target "$@"
