// The one translation unit that compiles tinygltf's implementation. The macros below must match
// the ones gltf_loader.cpp sets before including tiny_gltf.h (they change the TinyGLTF class).
// No stb: we never decode textures; the loader installs an image callback that ignores the bytes.
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_IMPLEMENTATION

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#include <tiny_gltf.h>
#pragma GCC diagnostic pop
