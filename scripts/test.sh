#!/usr/bin/env bash
# The tests: install what is missing, build, run the whole suite (C++ and Python,
# all registered with CTest). Ends with CTest's summary line.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
ctest --test-dir build -j "$(nproc)" --output-on-failure --timeout 900
