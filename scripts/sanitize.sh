#!/usr/bin/env bash
# Builds the C++ tests with AddressSanitizer and UndefinedBehaviorSanitizer and runs
# them, all but a few long-running validation cases that the Release suite runs and whose
# code the others cover under the sanitizers too: energy conservation and deposition, the
# periodic cell's servo runs (tens of thousands of steps; the cell's other tests and the 2D
# periodic triaxial run its code) and the undrained triaxial (the drained ones run its
# phases), the five seeds of strain-controlled cyclic triaxials (10 s in Release, over
# 300 s under the sanitizers; the stress-controlled cycles run the cyclic program), and the 3D
# variants of thread determinism, the surface-pressure plate, the lab
# triaxial, the direct shear box, the periodic oedometer, the periodic search's brute-force
# check, the rebuild-invariance run and the decomposed domain against one process (their 2D
# variants run the same loops; 3D code runs under the sanitizers in the other 3D tests).
# -O1 and line tables only (-g1): the build takes about 40 % less than at -O2 and the reports
# keep file and line.
# Without MPI: Open MPI's own allocations would drown the leak report.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEODEM_SANITIZE=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DGEODEM_WERROR=ON -DGEODEM_BUILD_BENCHMARKS=OFF -DGEODEM_WITH_MPI=OFF > /dev/null
cmake --build build-sanitize -j "$(nproc)" --target geodem_unit_tests geodem_validation_tests geodem_lab_validation_tests \
  geodem_fuzz_replay
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-sanitize -j "$(nproc)" -L "unit|validation" \
  -E "EnergyConservation|Deposit|ElementTests.CyclicModulus|PeriodicCellTest.ServoHolds|Triaxial.Undrained|(ThreadDeterminism|SurfacePressureTest|Triaxial|PeriodicSearchTest|ContactHistory.RebuildsDoNotChangeTheRun|DomainTest|DomainClumpsTest|DomainSparsTest|ElementTests).*3D" \
  --output-on-failure
