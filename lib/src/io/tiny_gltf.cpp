// The one translation unit that compiles tinygltf's implementation (its README.Debian: define
// TINYGLTF_IMPLEMENTATION in exactly one file). Configuration in tiny_gltf_config.h.
#define TINYGLTF_IMPLEMENTATION
#include "io/tiny_gltf_config.h"
