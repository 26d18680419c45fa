// tinygltf as every translation unit of the project includes it: the configuration macros change the
// TinyGLTF class, so they are set here once (a unit that set them differently would break the ODR).
// No stb here: the loader's image callback keeps the encoded bytes, and scene/textures.cpp decodes the
// images materials use (and reads external image files itself, under the buffers' folder rule).
#pragma once
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#include <tiny_gltf.h>
#pragma GCC diagnostic pop
