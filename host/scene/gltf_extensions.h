// What of a glTF file the loader does not render, said rather than dropped: extensions against the
// one table of those it supports (gltf_extensions.cpp), and core features it ignores.
#pragma once
#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace bp {

// The one-line error for a file the loader must refuse: an extension in extensionsRequired that
// it does not support, or Draco-compressed geometry without its uncompressed fallback. "" if none.
std::string gltf_extension_error(const nlohmann::json& gltf);

// One warning per unsupported extension the file uses (in extensionsUsed or an object's
// "extensions"), naming it, how many objects use it, and what the render does instead.
std::vector<std::string> gltf_extension_warnings(const nlohmann::json& gltf);

// One warning per core glTF feature present that the loader ignores (occlusionTexture, COLOR_0,
// skins, morph targets, animations other than a camera's).
std::vector<std::string> gltf_ignored_feature_warnings(const tinygltf::Model& model);

}  // namespace bp
