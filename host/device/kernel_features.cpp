#include "device/kernel_features.h"

namespace bp {

KernelFeatures features_for(const Scene& scene, bool light_sampling) {
  KernelFeatures f;
  f.phong = false;
  f.ggx = false;
  for (const SceneMaterial& m : scene.materials) {
    f.phong = f.phong || (!m.ggx && (m.ks.x > 0.0f || m.ks.y > 0.0f || m.ks.z > 0.0f));
    f.ggx = f.ggx || m.ggx;
  }
  f.light_sampling = light_sampling;
  f.shading_normals = scene.has_shading_normals();
  f.textures = scene.has_textures();
  f.normal_maps = scene.has_normal_maps();
  f.environment = scene.has_environment();
  f.transmission = scene.has_transmission();
  return f;
}

std::string kernel_options(const KernelFeatures& f) {
  return std::string("-DBP_FEATURE_PHONG=") + (f.phong ? "1" : "0") + " -DBP_FEATURE_GGX=" + (f.ggx ? "1" : "0") +
         " -DBP_FEATURE_LIGHT_SAMPLING=" + (f.light_sampling ? "1" : "0") +
         " -DBP_FEATURE_SHADING_NORMALS=" + (f.shading_normals ? "1" : "0") +
         " -DBP_FEATURE_TEXTURES=" + (f.textures ? "1" : "0") +
         " -DBP_FEATURE_NORMAL_MAPS=" + (f.normal_maps ? "1" : "0") +
         " -DBP_FEATURE_ENVIRONMENT=" + (f.environment ? "1" : "0") +
         " -DBP_FEATURE_TRANSMISSION=" + (f.transmission ? "1" : "0");
}

}  // namespace bp
