#!/usr/bin/env bash
# Time and peak memory of 3dvo-enc and 3dvo-dec versus vertex count and versus frame count, on
# the generated blob (3dvo-sample: an icosphere of 10 * 4^s + 2 vertices, deformed). Measured
# with GNU time (/usr/bin/time: wall seconds and maximum resident set size).
#
#   bench/scaling.sh [BUILD_DIR] [vertices|frames|all]     (defaults: build, all)
#
# Vertex count: subdivisions 3..8 (642 .. 655,362 vertices), 10 frames, one GOM of 10,
# lossless d3dmc; the decoder writes no OBJ files (hashes only).
# Frame count: subdivisions 4 (2,562 vertices), 50 .. 2000 frames in GOMs of 16, lossless
# d3dmc; the decoder writes every frame as OBJ (-o), as a player would.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "${1:-$here/../build}" && pwd)"
what="${2:-all}"
bin="$build/bin"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Runs a command under GNU time; prints "seconds peakMiB".
measure() {
  /usr/bin/time -f '%e %M' -o "$work/time" "$@" > "$work/out" 2> "$work/err" || {
    cat "$work/err" >&2
    exit 1
  }
  awk '{printf "%s %.1f", $1, $2 / 1024}' "$work/time"
}

if [ "$what" = all ] || [ "$what" = vertices ]; then
  echo "## versus vertex count (10 frames, GOMSize 10, lossless d3dmc)"
  printf '| %9s | %12s | %12s | %12s | %12s | %14s |\n' vertices "enc s" "enc MiB" "dec s" \
    "dec MiB" "dec Mvf/s"
  for s in 3 4 5 6 7 8; do
    rm -rf "$work/seq"
    "$bin/3dvo-sample" -o "$work/seq" --Subdivisions=$s --FrameCount=10 > /dev/null
    read -r es em <<< "$(measure "$bin/3dvo-enc" --InputMeshPattern="$work/seq/%04d.obj" \
      --FrameCount=10 --GOMSize=10 --BitstreamFile="$work/s.3dvo")"
    read -r ds dm <<< "$(measure "$bin/3dvo-dec" -i "$work/s.3dvo")"
    v=$((10 * 4 ** s + 2))
    printf '| %9d | %12s | %12s | %12s | %12s | %14.2f |\n' $v "$es" "$em" "$ds" "$dm" \
      "$(awk -v v=$v -v s="$ds" 'BEGIN {print v * 10 / s / 1e6}')"
  done
  echo
fi

if [ "$what" = all ] || [ "$what" = frames ]; then
  echo "## versus frame count (2,562 vertices, GOMSize 16, lossless d3dmc, decoder writes OBJ)"
  printf '| %7s | %12s | %12s | %12s | %12s | %12s |\n' frames "stream KiB" "enc s" "enc MiB" \
    "dec s" "dec MiB"
  rm -rf "$work/seq"
  "$bin/3dvo-sample" -o "$work/seq" --Subdivisions=4 --FrameCount=2000 > /dev/null
  for n in 50 200 800 2000; do
    read -r es em <<< "$(measure "$bin/3dvo-enc" --InputMeshPattern="$work/seq/%04d.obj" \
      --FrameCount=$n --GOMSize=16 --BitstreamFile="$work/f.3dvo")"
    rm -rf "$work/out$n"
    read -r ds dm <<< "$(measure "$bin/3dvo-dec" -i "$work/f.3dvo" -o "$work/out$n")"
    rm -rf "$work/out$n"
    printf '| %7d | %12d | %12s | %12s | %12s | %12s |\n' $n \
      "$(($(stat -c %s "$work/f.3dvo") / 1024))" "$es" "$em" "$ds" "$dm"
  done
fi
