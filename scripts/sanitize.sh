#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer: a Debug build (-O0) with TDVO_SANITIZE=ON in
# build-asan/, then the whole ctest suite under it. Any sanitizer report stops the test that
# made it (halt on the first error, leaks included), so the suite fails. Being a Debug build,
# it also checks determinism across build types: the conformance re-encoding tests compare this
# build's streams byte for byte with the committed ones, which a Release build made
# (docs/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t packages < <(grep -v '^\s*#' scripts/packages.txt | grep -v '^\s*$')
bash scripts/apt-install.sh "${packages[@]}"
jobs="$(nproc)"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DTDVO_SANITIZE=ON -DTDVO_BUILD_BENCHMARKS=OFF
cmake --build build-asan -j "$jobs"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
# The real-data reconstruction acceptance tests (minutes each in Release) and the Python and
# browser tests (no C++ of their own) are left to the Release run of scripts/test.sh: under
# ASan in a Debug build they would take most of CI's time without exercising other code.
exclude="${TDVO_SANITIZE_EXCLUDE:-^(ReconTvmc|ReconUu4cam|ReconDino|ReconSynth)[.]|^rd_|^player_}"
ctest --test-dir build-asan --output-on-failure -j "$jobs" -E "$exclude"
