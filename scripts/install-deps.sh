#!/usr/bin/env bash
# Installs the Debian packages geodem needs, only those missing.
# Usage: scripts/install-deps.sh [--with-peers]   (peers: LIGGGHTS, yade and LAMMPS, for benchmarks)
set -euo pipefail
packages=(g++ cmake ninja-build libeigen3-dev libxsimd-dev libtomlplusplus-dev libcli11-dev
          pybind11-dev python3-dev python3-pytest
          nlohmann-json3-dev zlib1g-dev libgtest-dev libgmock-dev libbenchmark-dev
          python3 python3-numpy python3-matplotlib clang-format
          libopenmpi-dev openmpi-bin)
if [[ "${1:-}" == "--with-peers" ]]; then packages+=(liggghts yade lammps); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
