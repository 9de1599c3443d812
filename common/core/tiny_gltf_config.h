// tinygltf as 3DVO uses it: compiled into the library (common/tiny_gltf_impl.cpp) without image
// decoding (images are not read) and without its own file access (common/gltf_io.cpp reads the
// files, with its limits). Include this instead of <tiny_gltf.h>.
#pragma once

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_FS
#include <tiny_gltf.h>
