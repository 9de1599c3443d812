// The one translation unit that compiles tinygltf's implementation (it is a header library).
// Its writer names std::ofstream even with TINYGLTF_NO_FS (tinygltf 2.7.0), so <fstream> first.
#include <fstream>
#define TINYGLTF_IMPLEMENTATION
#include "common/core/tiny_gltf_config.h"
