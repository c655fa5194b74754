#!/usr/bin/env bash
# Fuzzes the scenario reader with libFuzzer under AddressSanitizer and
# UndefinedBehaviorSanitizer (clang, from Debian), starting from the kept corpus, the
# malformed scenarios and the examples' scenarios. New inputs that reach new code are
# merged into tests/fuzz/corpus (kept in the repository; the test suite replays it).
# Usage: scripts/fuzz.sh [SECONDS=1800] [JOBS=1]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-1800}
jobs=${2:-1}
scripts/install-deps.sh
command -v clang++ >/dev/null || { apt-get install -y -q clang libclang-rt-14-dev; }
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DGEODEM_FUZZ=ON -DGEODEM_WITH_OPENMP=OFF -DGEODEM_WITH_MPI=OFF -DGEODEM_BUILD_BENCHMARKS=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
cmake --build build-fuzz --target geodem_scenario_fuzzer
work=build-fuzz/corpus
rm -rf "$work" && mkdir -p "$work"
cp tests/fuzz/corpus/* "$work"/ 2>/dev/null || true
find tests/malformed examples -name '*.toml' -exec cp {} "$work"/ \;
# Scenarios name other files (particle files, material files): run where they resolve.
build-fuzz/tests/geodem_scenario_fuzzer "$work" -max_total_time="$seconds" -jobs="$jobs" \
  -workers="$jobs" -max_len=4096 -timeout=10 -rss_limit_mb=2048 -dict=tests/fuzz/toml.dict \
  -print_final_stats=1
# Keep a minimal set that covers what the run covered.
mkdir -p build-fuzz/merged
build-fuzz/tests/geodem_scenario_fuzzer -merge=1 build-fuzz/merged "$work" tests/fuzz/corpus > /dev/null 2>&1
rm -f tests/fuzz/corpus/*
cp build-fuzz/merged/* tests/fuzz/corpus/
echo "corpus: $(ls tests/fuzz/corpus | wc -l) files in tests/fuzz/corpus"
