#!/bin/sh
# Fuzzes the progressive-mesh (.rpm) and irradiance-grid (.ivg) readers with libFuzzer (clang; on
# Debian: apt-get install clang libomp-dev). Not part of the CMake build nor of CI: run it by hand,
# niced, e.g. 30 minutes per reader:
#   bench/fuzz_readers.sh 1800
# Builds into build-fuzz/ with AddressSanitizer and UndefinedBehaviorSanitizer (the harnesses
# bench/fuzz/progressive_mesh_fuzzer.cpp and irradiance_grid_fuzzer.cpp, every file of common/),
# writes seed corpora with our own writers (bench/fuzz/make_reader_seeds.cpp), then runs each reader
# for the given number of seconds. Crashes land in build-fuzz/artifacts-{rpm,ivg}/.
set -eu
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${FUZZ_BUILD_DIR:-$root/build-fuzz}
cxx=${CXX_FUZZ:-clang++}
mkdir -p "$out/rpm-seeds" "$out/ivg-seeds" "$out/rpm-corpus" "$out/ivg-corpus" "$out/artifacts-rpm" \
  "$out/artifacts-ivg" "$out/rpm-work" "$out/ivg-work"
sources=$(find "$root/common" -name '*.cpp' | sort)
flags="-std=c++17 -g -O1 -fopenmp -I$root/common -isystem /usr/include/eigen3 -isystem /usr/include/OpenEXR
  -isystem /usr/include/Imath -fno-sanitize-recover=undefined"
libs="-lembree3 -lOpenEXR -lImath -lz"
if [ ! -x "$out/progressive_mesh_fuzzer" ] || [ -n "${FUZZ_REBUILD:-}" ]; then
  for harness in progressive_mesh_fuzzer irradiance_grid_fuzzer; do
    # shellcheck disable=SC2086
    $cxx $flags -fsanitize=fuzzer,address,undefined $sources "$root/bench/fuzz/$harness.cpp" $libs -o "$out/$harness"
  done
  # shellcheck disable=SC2086
  $cxx $flags $sources "$root/bench/fuzz/make_reader_seeds.cpp" $libs -o "$out/make_reader_seeds"
fi
rm -f "$out/rpm-seeds/"* "$out/ivg-seeds/"*
"$out/make_reader_seeds" "$out/rpm-seeds" "$out/ivg-seeds"
mv "$out/rpm-seeds/base.rply" "$out/rpm-work/base.rply"  # the base every .rpm input names
cd "$out"
RPM_FUZZ_DIR="$out/rpm-work" nice -n 19 "$out/progressive_mesh_fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 \
  -max_len=65536 -artifact_prefix="$out/artifacts-rpm/" -print_final_stats=1 "$out/rpm-corpus" "$out/rpm-seeds"
IVG_FUZZ_DIR="$out/ivg-work" exec nice -n 19 "$out/irradiance_grid_fuzzer" -max_total_time="$seconds" \
  -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$out/artifacts-ivg/" -print_final_stats=1 "$out/ivg-corpus" \
  "$out/ivg-seeds"
