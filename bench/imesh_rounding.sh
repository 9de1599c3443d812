#!/usr/bin/env bash
# How long the rounding of an I mesh (IMeshQuantStep, docs/prediction.md "I meshes coarser than
# the grid") stays in the frames after it: each sequence coded twice with the same grid,
# quantiser and B meshes, its I meshes lossless (IMeshQuantStep 1) and rounded to the quantiser
# step, and per frame the squared error of the rounded coding over the lossless one's, minus 1
# (3dvo-metrics' vertex RMSE, squared).
#
#   bench/imesh_rounding.sh BUILD_DIR OUT_DIR
#
# Needs ../shared/data/meshseq (horse-gallop, samba); a sequence that is not there is skipped,
# saying so.
set -euo pipefail
build="$(cd "${1:?usage: bench/imesh_rounding.sh BUILD_DIR OUT_DIR}" && pwd)"
out="${2:?usage: bench/imesh_rounding.sh BUILD_DIR OUT_DIR}"
repo="$(cd "$(dirname "$0")/.." && pwd)"
mkdir -p "$out"
run() {  # name cfg first-frame grid-bits extra-args...
  local name="$1" cfg="$2" first="$3" bits="$4"
  shift 4
  local pattern
  pattern="$(grep '^InputMeshPattern' "$repo/$cfg" | awk '{print $3}')"
  if [ ! -e "$repo/$(printf "$pattern" "$first")" ]; then
    echo "$name: skipped, $(printf "$pattern" "$first") is missing"
    return
  fi
  for step in 1 4; do
    local d="$out/$name-$step"
    rm -rf "$d" && mkdir -p "$d"
    (cd "$repo" && "$build/bin/3dvo-enc" -c "$cfg" --GridFit=object --GridBits="$bits" \
      --MotionQuantStep=4 --BMeshGap=8 --IMeshQuantStep="$step" "$@" -o "$d/s.3dvo" \
      --ReconMeshPattern="$d/%04d.obj" > "$d/enc.log")
    (cd "$repo" && "$build/bin/3dvo-metrics" -r "$pattern" --ReferenceFirstFrame="$first" \
      -t "$d/%04d.obj" --TestFirstFrame="$first" --CsvFile="$d/metrics.csv" > /dev/null)
  done
  /usr/bin/python3 - "$out/$name-1/metrics.csv" "$out/$name-4/metrics.csv" "$name" <<'PY'
import csv, sys
def rmse(path):
    return [float(r["vertex_rmse"]) for r in csv.DictReader(open(path)) if r["frame"].isdigit()]
a, b = rmse(sys.argv[1]), rmse(sys.argv[2])
print(sys.argv[3] + ": frame: squared error rounded / lossless - 1")
print(" ".join("%d:%+.0f%%" % (k, 100 * (y * y / (x * x) - 1)) for k, (x, y) in enumerate(zip(a, b)) if x > 0))
PY
}
run horse-gallop cfg/per-sequence/horse-gallop.cfg 1 12
run samba cfg/per-sequence/samba.cfg 0 11 --FrameCount=50
