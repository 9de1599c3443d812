#!/usr/bin/env bash
# Every figure of docs/performance.md, in one run: the machine, the CABAC engine, P-mesh and
# whole-stream coding, texture coding and the 4-camera decoding target, I meshes next to
# Draco's CLI, the Hausdorff metric, and the scaling tables. Benchmarks report the median of 3
# repetitions (CPU time, one thread unless stated).
#
#   bench/report.sh [BUILD_DIR] > report.txt        (default: build, a Release build)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "${1:-$here/../build}" && pwd)"
reps=(--benchmark_repetitions=3 --benchmark_report_aggregates_only=true)

echo "# machine"
lscpu | grep -E '^(Model name|CPU\(s\)|Thread|L1d|L2|L3)'
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
g++ --version | head -1
echo "flags: $(grep -E '^CMAKE_(BUILD_TYPE|CXX_FLAGS|CXX_FLAGS_RELEASE):' "$build/CMakeCache.txt" |
  tr '\n' ' ') plus -Wall -Wextra"
echo
echo "# CABAC engine (cabac_bench)"
"$build/bin/cabac_bench" "${reps[@]}" 2>&1 | grep _median
echo
echo "# P meshes, I meshes, whole streams (pmesh_bench)"
"$build/bin/pmesh_bench" "${reps[@]}" 2>&1 | grep -E '^sequence|_median'
echo
echo "# Textures: per-camera coding, shapes, whole streams (texture_bench)"
"$build/bin/texture_bench" "${reps[@]}" 2>&1 | grep -E '^sequence|_median'
echo
echo "# The 4-camera 644x486 target through 3dvo-dec (texture_target.sh)"
"$here/texture_target.sh" "$build" recon
echo
echo "# Hausdorff distance (metrics_bench)"
"$build/bin/metrics_bench" --benchmark_filter=Hausdorff "${reps[@]}" 2>&1 | grep _median
echo
echo "# I meshes next to Draco's CLI"
"$here/draco_cli.sh" "$build"
echo
echo "# scaling"
"$here/scaling.sh" "$build"
