#!/usr/bin/env bash
# Sets everything up, then runs the whole test suite with ctest (unit, integration,
# conformance). Tests that need ../shared/data say so and skip when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
