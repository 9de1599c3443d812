#!/usr/bin/env bash
# The browser player's decoding speed next to the native decoder (docs/performance.md, "In the
# browser"): makes the two streams of issue 20's targets from ../shared/data and runs
# bench/wasm_decode_bench.mjs (decoding speed) and bench/player_fps.mjs (the page playing it)
# on each.
#
#   uu-4cam: 3dvo-recon's tracked reconstruction of the first 100 frames of uu-4cam
#            (cfg/recon/uu-4cam.cfg), coded with its GOM list and the 4 cameras' textures
#            (d3dmc-lossless geometry, TextureMode bbox, TexturePadding mb128, TextureQP 28);
#   samba:   the 175 frames of samba with cfg/d3dmc-lossy.cfg (geometry only).
#
#   bash bench/browser_bench.sh [build folder, default build] [work folder, default a temporary
#                               one, removed at the end; given, it must be new or empty (or
#                               made by this script before), and the streams are kept and reused]
#
# Needs the WebAssembly decoder (bash scripts/wasm.sh) and the player's node_modules
# (build/player). Without the data, says so and exits 0.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
bin="$build/bin"
uu="$root/../shared/data/multiview/uu-4cam"
samba="$root/../shared/data/meshseq/samba"
runs="${TDVO_BENCH_RUNS:-5}"
if [ ! -f "$uu/cam1/video.avi" ] || [ ! -d "$samba" ]; then
  echo "browser_bench: $uu or $samba is absent: not measured (skipped)"
  exit 0
fi
if [ -n "${2:-}" ]; then
  # A given folder must be new, empty, or one this script made (its marker file): the script
  # replaces uu-import/ and recon/ in it, so it refuses any other folder.
  if [ -e "$2" ] && [ ! -f "$2/.browser_bench" ] &&
    { [ ! -d "$2" ] || [ -n "$(ls -A "$2")" ]; }; then
    echo "browser_bench: $2 exists and was not made by browser_bench.sh: give a new or empty" \
      "folder (nothing in it was touched)" >&2
    exit 1
  fi
  work="$(mkdir -p "$2" && cd "$2" && pwd)"
  touch "$work/.browser_bench"
else
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
cd "$root"

if [ ! -f "$work/uu.3dvo" ]; then
  echo "browser_bench: reconstructing 100 frames of uu-4cam (a few minutes)" >&2
  rm -rf "$work/uu-import"
  "$bin/3dvo-import" -i "$uu" -o "$work/uu-import" --Up=0,0,-1 > /dev/null
  [ -f "$work/recon/goms.txt" ] ||
    "$bin/3dvo-recon" -c cfg/recon/uu-4cam.cfg --Input="$uu" --FrameCount=100 \
      --Output="$work/recon" --Overwrite > /dev/null
  # The imported dataset (cameras, videos, masks) with the reconstruction as its meshes.
  /usr/bin/python3 - "$work/uu-import/dataset.json" "$work/recon" << 'EOF'
import json, os, sys
path, recon = sys.argv[1], sys.argv[2]
with open(path) as f:
    dataset = json.load(f)
dataset["meshes"] = os.path.join(recon, "%04d.obj")
with open(path, "w") as f:
    json.dump(dataset, f, indent=2)
EOF
  "$bin/3dvo-enc" -c cfg/d3dmc-lossless.cfg --Dataset="$work/uu-import" --FrameCount=100 \
    --GOMListFile="$work/recon/goms.txt" --TextureMode=bbox --TexturePadding=mb128 \
    --TextureQP=28 --BitstreamFile="$work/uu.3dvo" > /dev/null
fi
if [ ! -f "$work/samba.3dvo" ]; then
  "$bin/3dvo-enc" -c cfg/d3dmc-lossy.cfg -c cfg/per-sequence/samba.cfg \
    --BitstreamFile="$work/samba.3dvo" > /dev/null
fi

export TDVO_BIN_DIR="$bin" TDVO_PLAYER_DIR="${TDVO_PLAYER_DIR:-$build/player}"
for stream in uu samba; do
  echo "## $stream ($(stat -c %s "$work/$stream.3dvo") bytes)"
  node "$here/wasm_decode_bench.mjs" "$work/$stream.3dvo" "$runs"
  echo "### the player page playing it (software GL)"
  for size in 960x540 320x180; do
    node "$here/player_fps.mjs" "$work/$stream.3dvo" 10 "$size"
  done
  node "$here/player_fps.mjs" "$work/$stream.3dvo" 10 --no-draw
  echo
done
