#!/usr/bin/env bash
# Determinism across compilers, and ThreadSanitizer on the threaded stages.
#
#   scripts/clang-check.sh          clang build (build-clang/): the golden state hashes of
#                                   tests/validation/golden_state_test.cpp, which the gcc
#                                   builds also check, and the thread-determinism tests
#   scripts/clang-check.sh --tsan   clang + ThreadSanitizer (build-tsan/): the step on
#                                   2 and 3 threads (thread-determinism tests); LLVM's
#                                   OpenMP runtime is what TSan understands
#
# Needs clang, libomp-dev and libclang-rt-dev (Debian), installed here when missing.
# About 10 minutes on 2 cores for each build.
set -euo pipefail
cd "$(dirname "$0")/.."
need=()
for p in clang libomp-dev libclang-rt-dev; do
  dpkg -s "$p" > /dev/null 2>&1 || need+=("$p")
done
if ((${#need[@]})); then
  SUDO=$([[ $(id -u) -eq 0 ]] || echo sudo)
  $SUDO apt-get install -y -q --no-install-recommends "${need[@]}"
fi
dir=build-clang
flags=()
filter='GoldenState*:ThreadDeterminism*'
if [[ "${1:-}" == "--tsan" ]]; then
  dir=build-tsan
  flags=(-DCMAKE_CXX_FLAGS="-fsanitize=thread -g" -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread)
  filter='ThreadDeterminism*'
fi
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ \
  -DGEODEM_WITH_MPI=OFF -DGEODEM_BUILD_BENCHMARKS=OFF "${flags[@]}" > /dev/null
cmake --build "$dir" -j "$(nproc)" --target geodem_validation_tests
TSAN_OPTIONS="halt_on_error=1 suppressions=$PWD/scripts/tsan.supp" "$dir/tests/geodem_validation_tests" --gtest_filter="$filter"
