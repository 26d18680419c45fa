// tinygltf as every translation unit of the project includes it: the configuration macros change the
// TinyGLTF class, so they are set here once (a unit that set them differently would break the ODR).
// No stb: we never decode textures; the loader installs an image callback that ignores the bytes.
#pragma once
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#include <tiny_gltf.h>
#pragma GCC diagnostic pop
