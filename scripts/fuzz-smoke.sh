#!/usr/bin/env bash
# CI's short fuzzing run: builds the libFuzzer targets once, then fuzzes each for
# TDVO_FUZZ_SECONDS (default 20) on its corpus, two targets at a time. Fails on any finding.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${TDVO_FUZZ_SECONDS:-20}"
targets=(stream units imesh pmesh cfg obj ply gltf dataset png texture draco arrays)
mapfile -t packages < <(grep -v '^\s*#' scripts/packages.txt | grep -v '^\s*$')
bash scripts/apt-install.sh "${packages[@]}" clang libclang-rt-14-dev llvm
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTDVO_FUZZ=ON \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DTDVO_BUILD_TESTS=OFF -DTDVO_BUILD_BENCHMARKS=OFF > /dev/null
cmake --build build-fuzz -j "$(nproc)" --target fuzz_make_corpus \
  $(printf 'fuzz_%s ' "${targets[@]}")
build-fuzz/bin/fuzz_make_corpus . build-fuzz/fuzz/seeds
mkdir -p build-fuzz/fuzz/logs
status=0
run() {
  TDVO_FUZZ_SKIP_BUILD=1 bash scripts/fuzz.sh "$1" "$seconds" \
    > "build-fuzz/fuzz/logs/$1.log" 2>&1
}
for ((i = 0; i < ${#targets[@]}; i += 2)); do
  pids=()
  for t in "${targets[@]:i:2}"; do
    run "$t" &
    pids+=("$!:$t")
  done
  for p in "${pids[@]}"; do
    if wait "${p%%:*}"; then
      echo "fuzz-smoke: ${p#*:}: $(grep -h 'stat::number_of_executed_units' \
        "build-fuzz/fuzz/logs/${p#*:}.log" | tail -1) in ${seconds} s"
    else
      echo "fuzz-smoke: ${p#*:}: FINDING (build-fuzz/fuzz/logs/${p#*:}.log):"
      tail -40 "build-fuzz/fuzz/logs/${p#*:}.log"
      status=1
    fi
  done
done
exit "$status"
