// tinygltf (Debian's libtinygltf-dev, tiny_gltf.h) as pm uses it: compiled into pm::pm by
// tiny_gltf.cpp, with its JSON from Debian's nlohmann-json3-dev, and without image decoding
// or external images (pm reads geometry; images are kept by reference, never opened).
// Every file that includes tiny_gltf.h includes it through this header, so that all see the
// same configuration.
#pragma once

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
