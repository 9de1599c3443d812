#!/usr/bin/env bash
# Installs the 3DVO build BUILD_DIR into a fresh prefix, then builds the consumer program in a
# separate folder against the installed tree, through the CMake package (find_package; static,
# then shared libraries) and through pkg-config (tdvo-decoder.pc), and checks that each decodes
# STREAM to its expected MD5 lines and that none loads a video, image or TLS library (the
# geometry decoder links only Draco, zlib and libmd).
#
#   tests/consumer/run.sh BUILD_DIR STREAM.3dvo EXPECTED.md5
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
build="$(cd "$1" && pwd)"
stream="$2"
expected="$3"
work="$(mktemp -d "${TMPDIR:-/tmp}/tdvo-consumer.XXXXXX")"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
cp "$here/CMakeLists.txt" "$here/main.cpp" "$work/"
# ldd's output is taken whole before grep reads it: with pipefail, a grep -q that stops early
# would fail the pipeline through ldd's SIGPIPE.
no_media() {
  local libs
  libs="$(ldd "$1")"
  if grep -E 'libav|libsw|x264|libpng|libssl|libcrypto' <<< "$libs"; then
    echo "$1 loads the libraries above: the geometry decoder must not" >&2
    exit 1
  fi
}
grep ' geometry=' "$expected" > "$work/expected.md5"
# 1. CMake package, static and shared libraries.
for kind in static shared; do
  shared=OFF
  [ "$kind" = shared ] && shared=ON
  cmake -S "$work" -B "$work/build-$kind" -DCMAKE_PREFIX_PATH="$work/prefix" \
    -DTDVO_CONSUMER_SHARED=$shared > "$work/cmake-$kind.log"
  cmake --build "$work/build-$kind" > "$work/build-$kind.log"
  "$work/build-$kind/tdvo_consumer" "$stream" > "$work/$kind.md5"
  diff -u "$work/expected.md5" "$work/$kind.md5"
  no_media "$work/build-$kind/tdvo_consumer"
  if [ "$kind" = shared ] && ! grep -q libtdvo_decoder <<< "$(ldd "$work/build-$kind/tdvo_consumer")"; then
    echo "the shared consumer does not load libtdvo_decoder.so" >&2
    exit 1
  fi
  echo "consumer (CMake package, $kind libraries): $(wc -l < "$work/$kind.md5") MD5 lines equal to $(basename "$expected"), no media library loaded"
done
# 2. pkg-config (the linker takes the shared libraries where both kinds are installed).
export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig:$work/prefix/lib/$(gcc -print-multiarch)/pkgconfig"
read -r -a flags <<< "$(pkg-config --cflags --libs tdvo-decoder)"
c++ -O1 -o "$work/tdvo_consumer_pc" "$work/main.cpp" "${flags[@]}"
export LD_LIBRARY_PATH="$(pkg-config --variable=libdir tdvo-decoder)"
"$work/tdvo_consumer_pc" "$stream" > "$work/pc.md5"
diff -u "$work/expected.md5" "$work/pc.md5"
no_media "$work/tdvo_consumer_pc"
echo "consumer (pkg-config): $(wc -l < "$work/pc.md5") MD5 lines equal to $(basename "$expected"), no media library loaded"
