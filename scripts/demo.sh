#!/usr/bin/env bash
# Sets everything up, then encodes and decodes the bundled default sample: a deforming blob
# (2562 vertices, 30 frames) made by 3dvo-sample, coded with cfg/sample.cfg.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
out=demo-output
# A second run replaces the first one's files (--Overwrite), and nothing else.
mkdir -p "$out"
build/bin/3dvo-sample -o "$out/input" --Overwrite
build/bin/3dvo-enc -c cfg/sample.cfg --InputMeshPattern="$out/input/%04d.obj" \
  --BitstreamFile="$out/sample.3dvo" | tee "$out/encoder.log"
build/bin/3dvo-dec -i "$out/sample.3dvo" -o "$out/decoded" --Overwrite --verify "$out/encoder.log" \
  | tee "$out/decoder.log"
echo
echo "demo: input frames   $out/input/"
echo "demo: stream         $out/sample.3dvo ($(stat -c %s "$out/sample.3dvo") bytes)"
echo "demo: decoded frames $out/decoded/ (OBJ), hashes checked against the encoder's"
