#!/bin/sh
# Fuzzes the radiance PLY reader with libFuzzer (clang; on Debian: apt-get install clang).
# Not part of the CMake build nor of CI: run it by hand, e.g. for 30 minutes on one core, niced:
#   bench/fuzz_radiance_ply.sh 1800
# Builds into build-fuzz/ (next to this repository's other build folders), writes a seed corpus of
# files made by our own writer (bench/fuzz/make_radiance_ply_seeds.cpp), then runs the harness
# bench/fuzz/radiance_ply_fuzzer.cpp with AddressSanitizer and UndefinedBehaviorSanitizer.
# Crashes land in build-fuzz/artifacts/; the corpus grows in build-fuzz/corpus/.
set -eu
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${FUZZ_BUILD_DIR:-$root/build-fuzz}
cxx=${CXX_FUZZ:-clang++}
mkdir -p "$out/seeds" "$out/corpus" "$out/artifacts"
sources="$root/common/io/radiance_ply.cpp $root/common/radiance/radiance_field.cpp $root/common/radiance/basis.cpp
  $root/common/radiance/spherical_harmonics.cpp"
flags="-std=c++17 -g -O1 -I$root/common -fno-sanitize-recover=undefined"
if [ ! -x "$out/radiance_ply_fuzzer" ] || [ -n "${FUZZ_REBUILD:-}" ]; then
  # shellcheck disable=SC2086
  $cxx $flags -fsanitize=fuzzer,address,undefined $sources "$root/bench/fuzz/radiance_ply_fuzzer.cpp" \
    -o "$out/radiance_ply_fuzzer"
  # shellcheck disable=SC2086
  $cxx $flags $sources "$root/bench/fuzz/make_radiance_ply_seeds.cpp" -o "$out/make_radiance_ply_seeds"
fi
rm -f "$out/seeds/"*
"$out/make_radiance_ply_seeds" "$out/seeds"
tmp=/tmp
[ -d /dev/shm ] && [ -w /dev/shm ] && tmp=/dev/shm
cd "$out"
RPLY_FUZZ_TMP=$tmp exec nice -n 19 "$out/radiance_ply_fuzzer" -jobs=1 -workers=1 -max_total_time="$seconds" \
  -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$out/artifacts/" -print_final_stats=1 \
  "$out/corpus" "$out/seeds"
