// Kernels built with only the features a render uses (issue #5, "model only what a scene needs"):
// each feature is a preprocessor switch of the shared kernel code, on in the generic build.
#pragma once
#include "scene/scene.h"
#include <string>

namespace bp {

struct KernelFeatures {
  bool phong = true;           // a Phong lobe somewhere (ks > 0); off: every Phong material is Lambert
  bool ggx = true;             // glTF's metallic-roughness BRDF somewhere (kernels/shared/metallic_roughness.h)
  bool light_sampling = true;  // next-event estimation / per-patch shadow rays (kernels/shared/lights.h)
  bool shading_normals = true; // interpolated NORMAL corners (kernels/shared/surface.h); off: flat normals only
  bool textures = true;        // glTF textures (kernels/shared/texture.h); off: every material is its factors
  bool normal_maps = true;     // glTF normalTexture (kernels/shared/normal_map.h); off: NORMAL interpolated only
  bool environment = true;     // an environment light (kernels/shared/environment_map.h); off: rays leave into black
  bool transmission = true;    // thin-walled transmitters (kernels/shared/thin_glass.h); off: every surface is opaque
  bool glossy() const { return phong || ggx; }  // some f depends on the directions, not only Lambert
};

// What `scene` needs when light sampling is `light_sampling`.
KernelFeatures features_for(const Scene& scene, bool light_sampling);

// The build options that switch the features (-DBP_FEATURE_...=0|1).
std::string kernel_options(const KernelFeatures& features);

}  // namespace bp
