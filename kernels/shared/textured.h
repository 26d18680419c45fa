// The BSDF at a textured hit (DESIGN.md §6): its patch's mean material decides everything the
// weights read (the continuation s, the lobe choice, the density's shininess), the texel decides
// f (kd, ks, the lobe's exponent) and the emission. Untextured materials are left as they are.
#ifndef BP_SHARED_TEXTURED_H
#define BP_SHARED_TEXTURED_H
#include "shared/brdf.h"
#include "shared/texture.h"

// bsdf (from the patch's mean Material) with f and the emission of a texel's material.
BP_FN void bsdf_take_texel(Bsdf* bsdf, float3 kd, float3 ks, float shininess, float3 emission) {
  bsdf->kd = kd;
  bsdf->ks = ks;
  bsdf->shininess_f = shininess;
  bsdf->emission = emission;
}

// The same with the texel at barycentrics (b1, b2) of `triangle`, where its material is textured.
BP_FN void bsdf_apply_texel(Bsdf* bsdf, const TextureSet* set, bp_u32 material, bp_u32 triangle, float b1, float b2) {
  MaterialTextures mt = set->materials[material];
  if (!material_is_textured(&mt)) return;
  TexelMaterial t = texel_material(set, &mt, triangle, b1, b2);
  bsdf_take_texel(bsdf, t.kd, t.ks, t.shininess, t.emission);
}

#endif  // BP_SHARED_TEXTURED_H
