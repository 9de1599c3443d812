# The WebAssembly build (docs/wasm.md), configured by scripts/wasm.sh with emcmake: the geometry
# decoder's layers (core, entropy, geometry, views, bitstream, decoder) from the project's own
# CMake files, and the module decoder/wasm/ makes over tdvo::Decoder. Draco's decoder, zlib and
# libmd come from TDVO_WASM_DEPS (include/ and lib/), which scripts/wasm.sh compiles from
# Debian's source packages with the same toolchain.
if(NOT EMSCRIPTEN)
  message(FATAL_ERROR "TDVO_WASM needs the emscripten toolchain: run scripts/wasm.sh")
endif()
set(TDVO_WASM_DEPS "" CACHE PATH "Draco decoder, zlib and libmd built for wasm (include/, lib/)")
if(NOT EXISTS "${TDVO_WASM_DEPS}/lib/libdraco.a")
  message(FATAL_ERROR "TDVO_WASM_DEPS (${TDVO_WASM_DEPS}) has no lib/libdraco.a: run scripts/wasm.sh")
endif()

# The decoder reports errors as tdvo::Error exceptions: C++ exceptions on, at compile and link.
add_compile_options(-fexceptions)
add_link_options(-fexceptions)
set(CMAKE_POSITION_INDEPENDENT_CODE OFF)

# Imported targets under the names the layers' CMake files use.
foreach(pair draco::draco=libdraco.a ZLIB::ZLIB=libz.a PkgConfig::TDVO_LIBMD=libmd.a)
  string(REPLACE "=" ";" pair ${pair})
  list(GET pair 0 name)
  list(GET pair 1 file)
  add_library(${name} STATIC IMPORTED GLOBAL)
  set_target_properties(${name} PROPERTIES IMPORTED_LOCATION ${TDVO_WASM_DEPS}/lib/${file}
    INTERFACE_INCLUDE_DIRECTORIES ${TDVO_WASM_DEPS}/include)
endforeach()

function(tdvo_library target component)  # nothing is installed from this build
endfunction()

add_subdirectory(common)
add_subdirectory(bitstream)
add_subdirectory(decoder)
