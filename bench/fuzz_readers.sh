#!/bin/sh
# Fuzzes the progressive-mesh (.rpm) and irradiance-grid (.ivg) readers with libFuzzer (clang; on
# Debian: apt-get install clang libomp-dev). Not part of CI: run it by hand, niced, e.g. 30 minutes per
# reader:
#   bench/fuzz_readers.sh 1800
# Builds into build-fuzz/ (bench/fuzz/build.sh: the harnesses bench/fuzz/progressive_mesh_fuzzer.cpp and
# irradiance_grid_fuzzer.cpp over the cores, AddressSanitizer and UndefinedBehaviorSanitizer), writes
# seed corpora with our own writers (bench/fuzz/make_reader_seeds.cpp), then runs each reader for the
# given number of seconds. Crashes land in build-fuzz/artifacts-{rpm,ivg}/.
set -eu
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${FUZZ_BUILD_DIR:-$root/build-fuzz}
"$root/bench/fuzz/build.sh" progressive_mesh_fuzzer irradiance_grid_fuzzer make_reader_seeds
bin="$out/bench/fuzz"
mkdir -p "$out/rpm-seeds" "$out/ivg-seeds" "$out/rpm-corpus" "$out/ivg-corpus" "$out/artifacts-rpm" \
  "$out/artifacts-ivg" "$out/rpm-work" "$out/ivg-work"
rm -f "$out/rpm-seeds/"* "$out/ivg-seeds/"*
"$bin/make_reader_seeds" "$out/rpm-seeds" "$out/ivg-seeds"
mv "$out/rpm-seeds/base.rply" "$out/rpm-work/base.rply"  # the base every .rpm input names
cd "$out"
RPM_FUZZ_DIR="$out/rpm-work" nice -n 19 "$bin/progressive_mesh_fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 \
  -max_len=65536 -artifact_prefix="$out/artifacts-rpm/" -print_final_stats=1 "$out/rpm-corpus" "$out/rpm-seeds"
IVG_FUZZ_DIR="$out/ivg-work" exec nice -n 19 "$bin/irradiance_grid_fuzzer" -max_total_time="$seconds" \
  -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$out/artifacts-ivg/" -print_final_stats=1 "$out/ivg-corpus" \
  "$out/ivg-seeds"
