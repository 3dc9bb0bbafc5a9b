#!/bin/sh
# Fuzzes the radiance PLY reader with libFuzzer (clang; on Debian: apt-get install clang libomp-dev).
# Not part of CI: run it by hand, e.g. for 30 minutes on one core, niced:
#   bench/fuzz_radiance_ply.sh 1800
# Builds into build-fuzz/ (bench/fuzz/build.sh), writes a seed corpus of files made by our own writer
# (bench/fuzz/make_radiance_ply_seeds.cpp), then runs the harness bench/fuzz/radiance_ply_fuzzer.cpp
# with AddressSanitizer and UndefinedBehaviorSanitizer. Crashes land in build-fuzz/artifacts-rply/;
# the corpus grows in build-fuzz/rply-corpus/.
set -eu
seconds=${1:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${FUZZ_BUILD_DIR:-$root/build-fuzz}
"$root/bench/fuzz/build.sh" radiance_ply_fuzzer make_radiance_ply_seeds
bin="$out/bench/fuzz"
tmp=/tmp
[ -d /dev/shm ] && [ -w /dev/shm ] && tmp=/dev/shm
work="$tmp/rply_fuzz_$$"
mkdir -p "$out/rply-seeds" "$out/rply-corpus" "$out/artifacts-rply" "$work"
rm -f "$out/rply-seeds/"*
"$bin/make_radiance_ply_seeds" "$out/rply-seeds"
cd "$out"
RPLY_FUZZ_TMP=$work exec nice -n 19 "$bin/radiance_ply_fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 \
  -max_len=65536 -artifact_prefix="$out/artifacts-rply/" -print_final_stats=1 "$out/rply-corpus" "$out/rply-seeds"
