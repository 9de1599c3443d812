#!/usr/bin/env bash
# Fuzzes one target for a given time (docs/robustness.md):
#
#   bash scripts/fuzz.sh TARGET SECONDS [extra libFuzzer options]
#
# TARGET is one of: stream units imesh pmesh cfg obj ply gltf dataset png texture draco arrays.
# Builds the libFuzzer targets with clang in build-fuzz/ (TDVO_FUZZ=ON: ASan + UBSan +
# coverage), writes the seed corpora (build-fuzz/fuzz/seeds/), then runs the target on its
# working corpus build-fuzz/fuzz/work/TARGET
# (kept between runs; new inputs go there), the seeds and fuzz/regressions/TARGET. A finding
# (crash, sanitizer report, timeout, out-of-memory) is written to build-fuzz/fuzz/findings/TARGET/
# and the script exits non-zero; a clean run prints libFuzzer's final statistics
# (stat::number_of_executed_units is the exec count).
set -euo pipefail
cd "$(dirname "$0")/.."
target="${1:?usage: fuzz.sh TARGET SECONDS [libFuzzer options]}"
seconds="${2:?usage: fuzz.sh TARGET SECONDS [libFuzzer options]}"
shift 2
case "$target" in
  stream | units | imesh | pmesh | cfg | obj | ply | gltf | dataset | png | texture | draco | arrays) ;;
  *) echo "fuzz.sh: unknown target '$target'" >&2; exit 2 ;;
esac
build=build-fuzz
if [ "${TDVO_FUZZ_SKIP_BUILD:-0}" != 1 ]; then
  mapfile -t packages < <(grep -v '^\s*#' scripts/packages.txt | grep -v '^\s*$')
  bash scripts/apt-install.sh "${packages[@]}" clang libclang-rt-14-dev llvm
  CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTDVO_FUZZ=ON \
    -DTDVO_BUILD_TESTS=OFF -DTDVO_BUILD_BENCHMARKS=OFF > /dev/null
  cmake --build "$build" -j "$(nproc)" --target "fuzz_$target" fuzz_make_corpus
  "$build/bin/fuzz_make_corpus" . "$build/fuzz/seeds"
fi
work="$build/fuzz/work/$target"
findings="$build/fuzz/findings/$target"
mkdir -p "$work" "$findings"
corpora=("$work" "$build/fuzz/seeds/$target")
[ -d "fuzz/regressions/$target" ] && corpora+=("fuzz/regressions/$target")
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
# -timeout: seconds per input; -rss_limit_mb / -malloc_limit_mb: a larger resident size or a
# single allocation above 1 GiB is a finding (the I-mesh limits need at most ~0.8 GB in all).
"$build/bin/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2560 \
  -malloc_limit_mb=1024 -print_final_stats=1 -artifact_prefix="$findings/" "$@" "${corpora[@]}"
