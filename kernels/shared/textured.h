// The BSDF at a textured hit (docs/design.md §6): its patch's mean material decides everything the
// weights read (the continuation s, the lobe choice, the density's roughness), the texel decides
// f (base colour, metallic, roughness) and the emission. Untextured materials are left as they are.
#ifndef BP_SHARED_TEXTURED_H
#define BP_SHARED_TEXTURED_H
#include "shared/brdf.h"
#include "shared/texture.h"

// bsdf (from the patch's mean Material) with f and the emission of a texel's material. Textured
// materials are glTF's: the metallic-roughness BRDF, or where it reduces to Lambert (metallic and
// specular 0, the loader's choice) kd = base colour (1 - metallic).
BP_FN void bsdf_take_texel(Bsdf* bsdf, const TexelMaterial* t) {
  if (bsdf_is_ggx(bsdf)) {
    bsdf->metallic_roughness.base_color = t->base_color;
    bsdf->metallic_roughness.metallic = t->metallic;
    bsdf->metallic_roughness.alpha = ggx_alpha_from_roughness(t->roughness);
    if (t->specular_textured) {  // KHR_materials_specular's textures: f's Fresnel, not the weights' (density_*)
      bsdf->metallic_roughness.dielectric_f0 = t->dielectric_f0;
      bsdf->metallic_roughness.specular_weight = t->specular_weight;
    }
  } else {
    bsdf->kd = t->base_color * (1.0f - t->metallic);
  }
  bsdf->emission = t->emission;
}

// The same with the texel at barycentrics (b1, b2) of `triangle`, where its material is textured.
BP_FN void bsdf_apply_texel(Bsdf* bsdf, const TextureSet* set, bp_u32 material, bp_u32 triangle, float b1, float b2) {
  MaterialTextures mt = set->materials[material];
  if (!material_is_textured(&mt)) return;
  TexelMaterial t = texel_material(set, &mt, triangle, b1, b2);
  bsdf_take_texel(bsdf, &t);
}

#endif  // BP_SHARED_TEXTURED_H
