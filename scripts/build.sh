#!/usr/bin/env bash
# Configures and builds geodem (Release) in build/ with warnings as errors.
# Extra CMake arguments are passed through.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DGEODEM_WERROR=ON "$@" > /dev/null
cmake --build build -j "$(nproc)"
