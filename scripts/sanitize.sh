#!/usr/bin/env bash
# Builds the C++ tests with AddressSanitizer and UndefinedBehaviorSanitizer and runs
# them (all but the two long-running validation cases, which the Release suite runs).
# Without MPI: Open MPI's own allocations would drown the leak report.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEODEM_SANITIZE=ON \
  -DGEODEM_WERROR=ON -DGEODEM_BUILD_BENCHMARKS=OFF -DGEODEM_WITH_MPI=OFF > /dev/null
cmake --build build-sanitize -j "$(nproc)" --target geodem_unit_tests geodem_validation_tests geodem_lab_validation_tests \
  geodem_fuzz_replay
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-sanitize -j "$(nproc)" -L "unit|validation" -E "EnergyConservation|Deposit" \
  --output-on-failure
