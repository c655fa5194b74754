#!/usr/bin/env bash
# Fails when a C++ file is not clang-formatted (style: .clang-format at the root).
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "clang-format not installed; skipping the format check"; exit 0; }
files=$(git ls-files '*.cpp' '*.hpp')
bad=$(clang-format --dry-run --Werror $files 2>&1 | grep -c "error:" || true)
if [[ "$bad" != "0" ]]; then
  clang-format --dry-run --Werror $files 2>&1 | grep "error:" | head -20
  echo "$bad formatting differences: run clang-format -i on the files above"
  exit 1
fi
echo "format: ok"
