// Structs shared by host and device, declared once. No float3 here (16 bytes in OpenCL C):
// float arrays only, explicit padding; host/device/shared_types_check.cpp static_asserts the layout.
#ifndef BP_SHARED_TYPES_H
#define BP_SHARED_TYPES_H
#include "shared/compat.h"

#define BP_MATERIAL_DOUBLE_SIDED 1u
#define BP_MATERIAL_GGX 2u  // glTF metallic-roughness (kernels/shared/metallic_roughness.h), not Modified Phong
#define BP_MATERIAL_THIN_TRANSMITTER 4u  // KHR_materials_transmission, thin-walled (kernels/shared/thin_glass.h)
#define BP_MATERIAL_REFRACTOR 8u  // KHR_materials_transmission with a volume: refracts (kernels/shared/dielectric.h)

// A material (docs/design.md §6): Modified Phong, f = kd/pi + ks (n+2)/(2 pi) cos^n(alpha) (extras.phong and
// Lambert), or with BP_MATERIAL_GGX glTF 2.0's metallic-roughness BRDF (Appendix B: Lambert + GGX,
// Schlick Fresnel) from the fields after light_pdf_area, kd, ks and shininess then unused. Le one-sided.
typedef struct {
  float kd[3];
  float shininess;
  float ks[3];
  bp_u32 flags;          // BP_MATERIAL_*
  float emission[3];     // radiance Le, W sr^-1 m^-2
  float light_pdf_area;  // light sampling's density on this material's emitters: P(select) / area, m^-2 (lights.h)
  float base_color[3];   // BP_MATERIAL_GGX: baseColor, linear
  float metallic;
  float dielectric_f0[3];  // min(((ior - 1)/(ior + 1))^2 specularColor, 1) (KHR_materials_ior, KHR_materials_specular)
  float roughness;         // glTF's perceptual roughness; the GGX alpha is its square
  float specular_weight;   // KHR_materials_specular's specular: scales the dielectric Fresnel (f0 and f90)
  float ggx_pad[3];
  // A thin-walled transmitter (BP_MATERIAL_THIN_TRANSMITTER, docs/design.md §11): the share `transmission`
  // of the surface is a pane (thin_glass.h); the rest is the opaque BSDF scaled by 1 - transmission
  // (Phong's kd and ks at load, gltf_loader.cpp's read_transmission; GGX's f, metallic_roughness.h).
  float transmission_tint[3];  // baseColor x transmission: the pane's straight-through filter before Fresnel
  float transmission;          // the pane's share T of the surface (its mirror reflects F T)
  float ior;                   // of the pane's Fresnel F0 (KHR_materials_ior); a refractor's medium's index
  // BP_MATERIAL_REFRACTOR (KHR_materials_volume, thickness > 0): the share `transmission` refracts into
  // a medium that attenuates by exp(-attenuation d) over d metres (dielectric.h); the rest as above.
  float attenuation[3];        // m^-1: -ln(attenuationColor) / attenuationDistance
} Material;

// What shading needs of a triangle besides its geometry (the BVH owns the geometry).
// Patches: the triangle is split into patch_subdiv^2 sub-triangles (patch.h); a double-sided
// triangle owns twice as many, the back-side ones after the front-side ones. A triangle merged into a
// cluster (docs/design.md §12) owns none (patch_subdiv 0): the cluster_fans triangles of its cluster's
// fan, from cluster_first_fan in ClusterFan's array, own them.
typedef struct {
  float normal[3];       // geometric unit normal, front side (counter-clockwise winding)
  bp_u32 material;
  bp_u32 first_patch;
  bp_u32 patch_subdiv;
  float area;
  bp_u32 first_element;  // this triangle's first element (sub-triangle) in the ray-bundle pass
  bp_u32 cluster_first_fan;
  bp_u32 cluster_fans;   // 0: in no cluster
  bp_u32 pad0, pad1;
} TriangleShading;

// A cluster's fan triangle as a hit finds its patch: barycentrics b1 = dot(p - p0, dual1),
// b2 = dot(p - p0, dual2) (dual1 . e1 = 1, dual1 . e2 = 0 and the reverse, both in the plane), and the
// patches and elements it owns as a triangle of TriangleShading does.
typedef struct {
  float p0[3];
  bp_u32 first_patch;
  float dual1[3];
  bp_u32 patch_subdiv;
  float dual2[3];
  bp_u32 first_element;
} ClusterFan;

// Pinhole camera: a primary ray through pixel (px, py) with jitter (jx, jy) in [0,1)^2 is
//   dir = normalize(forward + (2 (px+jx)/W - 1) tan_half_x right - (2 (py+jy)/H - 1) tan_half_y up)
typedef struct {
  float position[3];
  float tan_half_fov_x;
  float right[3];
  float tan_half_fov_y;
  float up[3];
  bp_u32 width;
  float forward[3];
  bp_u32 height;
} CameraParams;

// Per-launch parameters of the path tracer.
typedef struct {
  bp_u32 seed;
  bp_u32 first_sample;       // index of this launch's first sample in each pixel
  bp_u32 samples_per_launch; // samples each work-item takes for its pixel
  bp_u32 max_depth;          // safety cap on path length (Russian roulette ends paths long before)
  float ray_epsilon;         // scene-scaled offset for secondary rays, metres
  float weight_ratio;        // N2 / N1 of the combination (docs/design.md §1)
  bp_u32 weight_mode;        // BP_WEIGHTS_*
  bp_u32 light_count;        // lights to sample (kernels/shared/lights.h); 0: no light sampling
  bp_u32 beta_heuristic;     // BP_BETA_*: the per-vertex beta of product weights (kernels/shared/weights.h)
  float rb_light_rate;       // the ray bundles' light-sample rate (BundleIteration), for the weights
  bp_u32 eye_direct_shared;  // 1: the eye vertex's direct light is split with RB (eye_segment_weights)
  bp_u32 shading_normals;    // 1: the scene has NORMAL corners to interpolate (surface.h)
  bp_u32 environment_width;  // the environment map where a ray leaves the scene (--environment,
  bp_u32 environment_height; //   kernels/shared/environment_map.h); 0 x 0: none
  bp_u32 environment_light;  // its index among the lights to sample; BP_NO_LIGHT: not sampled (p_L = 0)
  bp_u32 uv_slots;           // texcoord sets per triangle (kernels/shared/texture.h); 0: no textures
  bp_u32 rb_sun_own_samples; // RB's own samples of each directional light per iteration (--rb-sun own: 1), for the weights
  bp_u32 pad[3];
} PathTraceParams;

#define BP_WEIGHTS_NONE 0u
#define BP_WEIGHTS_PAPER 1u
#define BP_WEIGHTS_PRODUCT 2u

#define BP_BETA_CLAMPED 0u  // beta = min(1, N2 / (N1 P))
#define BP_BETA_BALANCE 1u  // beta = N2 / (N2 + N1 P)

// Per-pixel sums the path tracer writes each launch (no atomics: one work-item per pixel).
typedef struct {
  float weighted[3];         // sum of w_PT-weighted samples (the pt layer)
  bp_u32 rays;               // rays traced for this pixel in this launch
  float raw[3];              // sum of unweighted samples (pt_raw; equal to weighted without weights)
  bp_u32 nonfinite_samples;  // samples dropped because they were NaN or Inf
} PixelAccum;

#endif  // BP_SHARED_TYPES_H
