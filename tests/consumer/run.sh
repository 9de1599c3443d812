#!/usr/bin/env bash
# Installs the 3DVO build BUILD_DIR into a fresh prefix, then builds the consumer program in a
# separate folder against the installed tree, once through the CMake package (find_package)
# and once through pkg-config (tdvo-decoder.pc), and checks that both decode STREAM to its
# expected MD5 lines and that neither loads a video, image or TLS library (the geometry decoder
# links only Draco, zlib and libmd).
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
# 1. CMake package.
cmake -S "$work" -B "$work/build-cmake" -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/cmake.log"
cmake --build "$work/build-cmake" > "$work/build-cmake.log"
"$work/build-cmake/tdvo_consumer" "$stream" > "$work/cmake.md5"
grep ' geometry=' "$expected" > "$work/expected.md5"
diff -u "$work/expected.md5" "$work/cmake.md5"
no_media() {
  if ldd "$1" | grep -E 'libav|libsw|x264|libpng|libssl|libcrypto'; then
    echo "$1 loads the libraries above: the geometry decoder must not" >&2
    exit 1
  fi
}
no_media "$work/build-cmake/tdvo_consumer"
echo "consumer (CMake package): $(wc -l < "$work/cmake.md5") MD5 lines equal to $(basename "$expected"), no media library loaded"
# 2. pkg-config.
export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig:$work/prefix/lib/$(gcc -print-multiarch)/pkgconfig"
read -r -a flags <<< "$(pkg-config --cflags --libs tdvo-decoder)"
c++ -O1 -o "$work/tdvo_consumer_pc" "$work/main.cpp" "${flags[@]}"
"$work/tdvo_consumer_pc" "$stream" > "$work/pc.md5"
diff -u "$work/expected.md5" "$work/pc.md5"
no_media "$work/tdvo_consumer_pc"
echo "consumer (pkg-config): $(wc -l < "$work/pc.md5") MD5 lines equal to $(basename "$expected"), no media library loaded"
