#!/usr/bin/env bash
# Sets everything up, then runs the main job on the bundled default: a textured 3D video object
# (the deforming blob of 3dvo-synth, filmed by 8 cameras) is encoded with cfg/sample.cfg,
# decoded (mesh frames, camera images, hashes checked against the encoder's), and shown: 16
# free-viewpoint views of one frame rendered to PNG, and the command that plays the stream in a
# browser (3dvo-play: the page decodes it, with the WebAssembly decoder that scripts/wasm.sh
# builds as part of the setup: about 5 to 10 minutes the first time, on 2 cores).
#
# TDVO_DEMO_OUT (default demo-output in the repository) is the output folder; TDVO_DEMO_SKIP_SETUP=1
# skips the setup and TDVO_BIN_DIR (default build/bin) names the apps (the test of this script,
# ctest `demo`, runs it on a built tree). Relative paths in them are relative to the folder the
# script is run from.
set -euo pipefail
absolute() { case "$1" in /*) printf '%s' "$1" ;; *) printf '%s/%s' "$PWD" "$1" ;; esac; }
[ -z "${TDVO_DEMO_OUT:-}" ] || TDVO_DEMO_OUT="$(absolute "$TDVO_DEMO_OUT")"
[ -z "${TDVO_BIN_DIR:-}" ] || TDVO_BIN_DIR="$(absolute "$TDVO_BIN_DIR")"
cd "$(dirname "$0")/.."
if [ "${TDVO_DEMO_SKIP_SETUP:-0}" != 1 ]; then
  bash scripts/setup.sh
  bash scripts/wasm.sh
  cmake --build build --target player_wasm  # the module into build/player/wasm/
fi
out="${TDVO_DEMO_OUT:-demo-output}"
bin="${TDVO_BIN_DIR:-build/bin}"
# A second run replaces the first one's files (--Overwrite), and nothing else.
mkdir -p "$out"
"$bin/3dvo-synth" -o "$out/rig" --FrameCount=30 --Overwrite
"$bin/3dvo-enc" -c cfg/sample.cfg --Dataset="$out/rig" --BitstreamFile="$out/sample.3dvo" \
  | tee "$out/encoder.log"
"$bin/3dvo-dec" -i "$out/sample.3dvo" -o "$out/decoded" --Overwrite --verify "$out/encoder.log" \
  | tee "$out/decoder.log"
# Frame 12 from 16 views around the object, every other one between two cameras (the ring's 8
# cameras are 45 degrees apart; they surround the object, so the default path is a full turn).
"$bin/3dvo-render" -i "$out/decoded" -o "$out/view" --Overwrite --FirstFrame=12 --FrameCount=1 \
  --OrbitSteps=16
echo
echo "demo: input (cameras + meshes) $out/rig/"
echo "demo: stream                   $out/sample.3dvo ($(stat -c %s "$out/sample.3dvo") bytes)"
echo "demo: decoded                  $out/decoded/ (OBJ frames, one PNG folder per camera," \
  "dataset.json), hashes checked against the encoder's"
echo "demo: free views of frame 12  $(realpath "$out/view")/0000.png .. 0015.png (rendered from" \
  "the decoded object; 0001.png lies between two cameras)"
# The web player of this build (build/player), and whether it holds the WebAssembly decoder.
build="$(realpath "$bin/..")"
if [ ! -x "$bin/3dvo-play" ]; then
  echo "demo: no web player in this build (it needs node and npm: docs/rendering.md)"
  exit 0
fi
if [ ! -f "$build/player/wasm/tdvo_decoder.wasm" ]; then
  echo "demo: the web player needs the WebAssembly decoder, not built here (about 10 minutes):"
  echo "      bash $PWD/scripts/wasm.sh && cmake --build $build"
fi
echo "demo: play it in a browser     $(realpath "$bin/3dvo-play") $(realpath "$out/sample.3dvo")"
echo "      (serves the page and the stream on 127.0.0.1 and prints the URL to open; Ctrl-C stops)"
