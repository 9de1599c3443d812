#!/usr/bin/env bash
# Issue 17 point 1's figures: what the output order (VERTEX_ORDER units) and connectivity reuse
# (RandomAccessPeriod) cost or save, on horse-gallop, samba and pcow with their per-sequence cfg
# and cfg/d3dmc-lossy.cfg at MotionQuantStep 8. Skipped, saying so, when ../shared/data is
# absent. Run from anywhere; paths in cfg/per-sequence/ are relative to the repository root.
#
#   bench/order_cost.sh [BUILD_DIR]      (default: build)
#
# For each sequence and RandomAccessPeriod 1 (a random access point at every GOM) and 4, with
# InputTriangleOrder 1 (the input's triangle list, the default) and 0 (vertices only): total
# stream bytes, I-mesh bytes, VERTEX_ORDER bytes, their share of the stream and the order's
# bits per vertex per random access point (RA points: one per RandomAccessPeriod GOMs).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
enc="$build/bin/3dvo-enc"
cd "$root"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

printf "%-13s %3s %4s %9s %8s %8s %6s %9s\n" sequence RAP tris bytes "I mesh" order "order%" "bits/v/RA"
for seq in horse-gallop samba pcow; do
  cfg="cfg/per-sequence/$seq.cfg"
  pattern="$(sed -n 's/^InputMeshPattern *: *//p' "$cfg")"
  first="$(sed -n 's/^FirstFrame *: *//p' "$cfg")"
  frames="$(sed -n 's/^FrameCount *: *//p' "$cfg")"
  gom="$(sed -n 's/^GOMSize *: *//p' "$cfg")"
  # shellcheck disable=SC2059
  firstFile="$(printf "$pattern" "$first")"
  if [ ! -e "$firstFile" ]; then
    echo "$seq: skipped ($firstFile not found; see the README of the shared data folder)"
    continue
  fi
  vertices="$(zcat -f "$firstFile" | grep -c '^v ')"
  goms=$(((frames + gom - 1) / gom))
  for period in 1 4; do
    ra=$(((goms + period - 1) / period))
    for tris in 1 0; do
      "$enc" -c "$cfg" -c cfg/d3dmc-lossy.cfg --MotionQuantStep=8 --RandomAccessPeriod=$period \
        --InputTriangleOrder=$tris -o "$tmp/x.3dvo" > "$tmp/log"
      line="$(grep '^bytes' "$tmp/log")"
      total="$(echo "$line" | sed 's/^bytes *: *\([0-9]*\).*/\1/')"
      imesh="$(echo "$line" | sed 's/.*I meshes \([0-9]*\).*/\1/')"
      order="$(echo "$line" | sed 's/.*vertex orders \([0-9]*\).*/\1/')"
      awk -v s="$seq" -v p="$period" -v t="$tris" -v b="$total" -v i="$imesh" -v o="$order" \
        -v ra="$ra" -v n="$vertices" 'BEGIN {
          printf "%-13s %3d %4d %9d %8d %8d %5.1f%% %9.2f\n", s, p, t, b, i, o, 100 * o / b,
                 8 * o / (ra * n) }'
    done
  done
done
