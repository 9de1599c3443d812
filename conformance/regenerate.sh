#!/usr/bin/env bash
# Regenerates every conformance stream and its expected MD5 log from conformance/cfg/*.cfg and
# the committed inputs. Run it when the syntax version (kSyntaxVersion) or the decoding process
# changes, then review and commit the changed streams and logs together with the change.
#
#   conformance/regenerate.sh [BUILD_DIR]      (default: build)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "${1:-$here/../build}" && pwd)"
enc="$build/bin/3dvo-enc"
dec="$build/bin/3dvo-dec"
cd "$here"
for cfg in cfg/*.cfg; do
  name="$(basename "$cfg" .cfg)"
  "$enc" -c "$cfg" --BitstreamFile="streams/$name.3dvo" > "streams/$name.enc.log"
  grep '^MD5 ' "streams/$name.enc.log" > "streams/$name.md5"
  rm "streams/$name.enc.log"
  # The decoder must reproduce the encoder's reconstruction exactly.
  "$dec" -i "streams/$name.3dvo" --verify "streams/$name.md5" > /dev/null
  printf "%-30s %7d bytes  %3d MD5 lines\n" "$name" "$(stat -c %s "streams/$name.3dvo")" \
    "$(wc -l < "streams/$name.md5")"
done
