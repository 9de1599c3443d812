#!/usr/bin/env bash
# Sets everything up, then runs the whole test suite with ctest (unit, integration,
# conformance, Python, browser). Tests that need ../shared/data say so and skip when it is
# absent. The WebAssembly decoder is built first (scripts/wasm.sh: Debian's emscripten and the
# Debian sources of Draco, zlib and libmd; about 4 minutes on 2 cores) so that its browser test
# (wasm_browser_test) runs rather than skips.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/wasm.sh
cmake --build build --target player_wasm  # the module into build/player/wasm/ for the page's tests
ctest --test-dir build --output-on-failure -j "$(nproc)"
