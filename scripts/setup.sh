#!/usr/bin/env bash
# Installs the Debian packages in scripts/packages.txt (when any is missing) and builds 3DVO in
# build/ (Release). Used by scripts/demo.sh and scripts/test.sh; run as root on Debian 12.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t packages < <(grep -v '^\s*#' scripts/packages.txt | grep -v '^\s*$')
bash scripts/apt-install.sh "${packages[@]}"
jobs="$(nproc)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"
