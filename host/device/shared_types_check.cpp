// The structs of kernels/shared/types.h are compiled by both compilers: their host layout must be
// what OpenCL C gives them (4-byte scalars, no implicit padding, sizes multiple of 16).
#include "kernels/shared/types.h"
#include <cstddef>

#define BP_CHECK_LAYOUT(T, size) \
  static_assert(sizeof(T) == (size), #T " changed size: update the kernels and this check"); \
  static_assert(sizeof(T) % 16 == 0, #T " must be a multiple of 16 bytes")

BP_CHECK_LAYOUT(Material, 128);
static_assert(offsetof(Material, ks) == 16 && offsetof(Material, emission) == 32);
static_assert(offsetof(Material, base_color) == 48 && offsetof(Material, dielectric_f0) == 64 &&
              offsetof(Material, specular_weight) == 80);
static_assert(offsetof(Material, transmission_tint) == sizeof(Material) - 32 && offsetof(Material, ior) == sizeof(Material) - 16,
              "the transmission fields end Material");
BP_CHECK_LAYOUT(TriangleShading, 48);
static_assert(offsetof(TriangleShading, material) == 12 && offsetof(TriangleShading, area) == 24 &&
              offsetof(TriangleShading, cluster_fans) == 36);
BP_CHECK_LAYOUT(ClusterFan, 48);
static_assert(offsetof(ClusterFan, dual1) == 16 && offsetof(ClusterFan, dual2) == 32);
BP_CHECK_LAYOUT(CameraParams, 64);
static_assert(offsetof(CameraParams, right) == 16 && offsetof(CameraParams, forward) == 48);
BP_CHECK_LAYOUT(PathTraceParams, 80);
static_assert(offsetof(PathTraceParams, environment_width) == 48 && offsetof(PathTraceParams, environment_light) == 56 &&
              offsetof(PathTraceParams, rb_sun_own_samples) == 64);
BP_CHECK_LAYOUT(PixelAccum, 32);
static_assert(offsetof(PixelAccum, raw) == 16);

#include "kernels/shared/texture.h"
BP_CHECK_LAYOUT(TextureView, 48);
BP_CHECK_LAYOUT(MaterialTextures, 96);
static_assert(offsetof(MaterialTextures, base_color_factor) == 16 && offsetof(MaterialTextures, normal) == 52 &&
              offsetof(MaterialTextures, specular) == 60 && offsetof(MaterialTextures, specular_f0) == 72);

#include "kernels/shared/bundle_types.h"
BP_CHECK_LAYOUT(BundleElement, 64);
BP_CHECK_LAYOUT(BundleIteration, 160);
static_assert(offsetof(BundleIteration, environment_width) == 128 && offsetof(BundleIteration, environment_light) == 136 && offsetof(BundleIteration, contact_depth) == 140 &&
              offsetof(BundleIteration, sun_own_samples) == 144);
static_assert(offsetof(BundleIteration, omega_prev) == 64 && offsetof(BundleIteration, weight_ratio) == 88 &&
              offsetof(BundleIteration, omega_next) == 96);
BP_CHECK_LAYOUT(EyeHit, 48);
static_assert(offsetof(EyeHit, filter) == 32);

#include "kernels/shared/lights.h"
BP_CHECK_LAYOUT(Light, 112);
static_assert(offsetof(Light, axis) == 48 && offsetof(Light, intensity) == 64 && offsetof(Light, cos_inner) == 80 &&
              offsetof(Light, tree_trail) == 84 &&
              offsetof(Light, triangle) == 96);

#include "kernels/shared/light_tree.h"
BP_CHECK_LAYOUT(LightTreeNode, 64);
static_assert(offsetof(LightTreeNode, hi) == 16 && offsetof(LightTreeNode, axis) == 32 &&
              offsetof(LightTreeNode, child) == 48);
BP_CHECK_LAYOUT(LightReceiver, 48);
static_assert(offsetof(LightReceiver, normal) == 16 && offsetof(LightReceiver, light) == 28 &&
              offsetof(LightReceiver, infinite_visibility) == 32);
