// The one translation unit that compiles tinygltf's implementation, with the configuration of
// scene/tinygltf.h.
#define TINYGLTF_IMPLEMENTATION
#include "scene/tinygltf.h"
