#!/usr/bin/env bash
# Builds the geometry decoder as WebAssembly (docs/wasm.md): build-wasm/tdvo_decoder.js and
# build-wasm/tdvo_decoder.wasm. Run as root on Debian 12 (like scripts/setup.sh): installs
# Debian's emscripten when missing, fetches the Debian source packages of Draco, zlib and libmd
# (apt-get source; adds a deb-src entry when there is none), compiles what the decoder needs of
# them with emcc (Draco: its own CMake, decoder object libraries only), then builds the
# project's decoder layers with the project's CMake (-DTDVO_WASM=ON). Steps already done are
# skipped; delete build-wasm/ to start over.
#
# Usage: bash scripts/wasm.sh [build folder, default build-wasm]
set -euo pipefail
cd "$(dirname "$0")/.."
source_dir="$PWD"
out="$(realpath -m "${1:-build-wasm}")"
jobs="$(nproc)"

# emscripten 3.1.6 (Debian) runs its tools with node, which must find Debian's node modules
# (acorn) when node is not Debian's own; Draco's CMake asks for EMSCRIPTEN.
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"
export EMSCRIPTEN=/usr/share/emscripten
bash scripts/apt-install.sh emscripten dpkg-dev

deps="$out/deps"
mkdir -p "$deps/src" "$deps/lib" "$deps/include"

# --- Debian source packages -------------------------------------------------------------------
if [ ! -d "$deps/src/draco" ] || [ ! -d "$deps/src/zlib" ] || [ ! -d "$deps/src/libmd" ]; then
  if ! grep -rqs '^Types:.*deb-src' /etc/apt/sources.list.d/ &&
     ! grep -qs '^deb-src' /etc/apt/sources.list; then
    sed 's/^Types:.*/Types: deb-src/' /etc/apt/sources.list.d/debian.sources \
      >/etc/apt/sources.list.d/debian-src.sources
  fi
  # The newest source of each (a security update's, when there is one); a mirror that lacks
  # it (seen: debian-security's zlib 1.2.13.dfsg-1+deb12u1 answered 404) gets the release's.
  release="$(. /etc/os-release && echo "$VERSION_CODENAME")"
  fetch() { (cd "$deps/src" && apt-get source --download-only "$1" >/dev/null 2>&1); }
  updated=0
  for package in draco zlib libmd; do
    fetch "$package" && continue
    if [ "$updated" = 0 ]; then
      apt-get update -qq
      updated=1
      fetch "$package" && continue
    fi
    echo "wasm.sh: the newest source of $package cannot be fetched; using $release's" >&2
    (cd "$deps/src" && apt-get source --download-only "$package/$release" >/dev/null)
  done
  for package in draco zlib libmd; do
    rm -rf "$deps/src/$package"
    dsc="$(ls "$deps/src/${package}"_*.dsc | head -n1)"
    # The Debian patches are applied: these are the sources of the native libraries.
    dpkg-source --no-check -x "$dsc" "$deps/src/$package" >/dev/null
  done
fi

# --- zlib (crc32, and the gzip reader of common/core/file_io.cpp) -------------------------------
if [ ! -f "$deps/lib/libz.a" ]; then
  rm -rf "$deps/obj/zlib" && mkdir -p "$deps/obj/zlib"
  # zconf.h as zlib's configure makes it on a system with unistd.h: the template.
  cp "$deps/src/zlib/zconf.h.in" "$deps/include/zconf.h"
  for c in adler32 compress crc32 deflate gzclose gzlib gzread gzwrite infback inffast inflate \
           inftrees trees uncompr zutil; do
    emcc -O2 -DHAVE_UNISTD_H -I"$deps/include" -c "$deps/src/zlib/$c.c" -o "$deps/obj/zlib/$c.o"
  done
  emar rcs "$deps/lib/libz.a" "$deps/obj/zlib/"*.o
  cp "$deps/src/zlib/zlib.h" "$deps/include/"
fi

# --- libmd (MD5 only, for common/core/md5.cpp) --------------------------------------------------
if [ ! -f "$deps/lib/libmd.a" ]; then
  rm -rf "$deps/obj/libmd" && mkdir -p "$deps/obj/libmd"
  : >"$deps/obj/libmd/config.h"  # little-endian target: nothing to configure
  emcc -O2 -I"$deps/obj/libmd" -I"$deps/src/libmd/include" -c "$deps/src/libmd/src/md5.c" \
    -o "$deps/obj/libmd/md5.o"
  emar rcs "$deps/lib/libmd.a" "$deps/obj/libmd/md5.o"
  cp "$deps/src/libmd/include/md5.h" "$deps/include/"
fi

# --- Draco: its own CMake, the decoder's object libraries only ----------------------------------
# (-w: Draco's own warnings are not ours to fix, as for tinygltf in common/core)
draco_decoder_parts=(draco_attributes draco_compression_attributes_dec
  draco_compression_attributes_pred_schemes_dec draco_compression_bit_coders
  draco_compression_decode draco_compression_entropy draco_compression_mesh_traverser
  draco_compression_mesh_dec draco_compression_options draco_compression_point_cloud_dec
  draco_core draco_dec_config draco_mesh draco_metadata_dec draco_metadata draco_point_cloud
  draco_points_dec)
if [ ! -f "$deps/lib/libdraco.a" ]; then
  emcmake cmake -S "$deps/src/draco" -B "$deps/draco-build" -DCMAKE_BUILD_TYPE=Release \
    -DDRACO_JS_GLUE=OFF -DDRACO_TESTS=OFF "-DCMAKE_CXX_FLAGS=-fexceptions -w" >/dev/null
  cmake --build "$deps/draco-build" -j "$jobs" --target "${draco_decoder_parts[@]}" >/dev/null
  objects=()
  for part in "${draco_decoder_parts[@]}"; do
    while IFS= read -r -d '' o; do objects+=("$o"); done \
      < <(find "$deps/draco-build/CMakeFiles/$part.dir" -name '*.o' -print0)
  done
  emar rcs "$deps/lib/libdraco.a" "${objects[@]}"
  mkdir -p "$deps/include/draco"
  (cd "$deps/src/draco/src" && find draco -name '*.h' -exec cp --parents {} "$deps/include/" \;)
  cp "$deps/draco-build/draco/draco_features.h" "$deps/include/draco/"
fi

# --- The project's decoder layers and the module ------------------------------------------------
emcmake cmake -S "$source_dir" -B "$out" -DCMAKE_BUILD_TYPE=Release -DTDVO_WASM=ON \
  -DTDVO_WASM_DEPS="$deps" >/dev/null
cmake --build "$out" -j "$jobs"
ls -l "$out/tdvo_decoder.js" "$out/tdvo_decoder.wasm"
