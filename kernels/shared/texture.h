// glTF textures (docs/design.md §6): every image's texels in one buffer (RGBA8, one bp_u32 per texel, rows
// top to bottom as glTF's uv (0, 0) is the image's top-left corner), a view per use of an image by
// a material (sampler, KHR_texture_transform, texcoord set, sRGB or linear), and the material's
// factors, so a hit's base colour, metallic, roughness, emission, specular and alpha are evaluated
// the same way here, in the host's per-patch means and in the host tests. No OpenCL image objects.
#ifndef BP_SHARED_TEXTURE_H
#define BP_SHARED_TEXTURE_H
#include "shared/compat.h"

#define BP_WRAP_REPEAT 0u
#define BP_WRAP_CLAMP_TO_EDGE 1u
#define BP_WRAP_MIRRORED_REPEAT 2u
#define BP_TEXTURE_WRAP_MASK 3u
#define BP_TEXTURE_WRAP_T_SHIFT 2u     // flags: wrap_s | wrap_t << 2
#define BP_TEXTURE_NEAREST 16u         // the sampler's magFilter is NEAREST (else bilinear)
#define BP_TEXTURE_SRGB 32u            // RGB are sRGB-encoded (baseColorTexture, emissiveTexture)
#define BP_NO_TEXTURE 0xffffffffu
#define BP_MAX_UV_SLOTS 2u             // distinct TEXCOORD_n sets one material may use

// One use of an image: where its texels are, how it is sampled, and which texcoords it reads.
typedef struct {
  bp_u32 first_texel;  // into the texel buffer
  bp_u32 width;
  bp_u32 height;
  bp_u32 flags;        // BP_WRAP_* of s and t, BP_TEXTURE_*
  float transform[6];  // KHR_texture_transform: uv' = (t0 t2; t1 t3) uv + (t4, t5), column-major like glTF
  bp_u32 uv_slot;      // which of the triangle's texcoord sets (< BP_MAX_UV_SLOTS)
  bp_u32 pad;
} TextureView;

// A material's textures (TextureView indices, BP_NO_TEXTURE: none) and the core-glTF factors they
// multiply (the rest of a textured material is its Material's: shared/metallic_roughness.h).
typedef struct {
  bp_u32 base_color;          // RGB sRGB, A linear
  bp_u32 metallic_roughness;  // G roughness, B metallic, linear
  bp_u32 emissive;            // RGB sRGB
  float alpha_cutoff;         // alphaMode MASK: alpha below it is no surface; 0: opaque
  float base_color_factor[4]; // linear RGBA
  float emissive_factor[3];   // emissiveFactor x emissiveStrength, W sr^-1 m^-2
  float metallic_factor;
  float roughness_factor;
  bp_u32 normal;              // normalTexture: RGB linear, a tangent-space normal (shared/normal_map.h)
  float normal_scale;         // normalTexture.scale: multiplies the map's x and y
  bp_u32 specular;            // KHR_materials_specular's specularTexture: A linear
  bp_u32 specular_color;      // its specularColorTexture: RGB sRGB
  float specular_factor;      // specularFactor
  float specular_f0[3];       // ((ior - 1)/(ior + 1))^2 specularColorFactor, before the texel and the cap at 1
  float pad[3];
} MaterialTextures;

// Everything a texel lookup reads. uv_slots: texcoord sets stored per triangle (texcoords holds
// uv_slots x 3 corners x (u, v) floats per triangle).
typedef struct {
  BP_GLOBAL const TextureView* views;
  BP_GLOBAL const bp_u32* texels;
  BP_GLOBAL const MaterialTextures* materials;  // per material, like the Material buffer
  BP_GLOBAL const float* texcoords;
  bp_u32 uv_slots;
} TextureSet;

// sRGB transfer function, decoded (IEC 61966-2-1): c/12.92 below 0.04045, else ((c + 0.055)/1.055)^2.4.
BP_FN float srgb_to_linear(float c) {
  return c <= 0.04045f ? c * (1.0f / 12.92f) : pow((c + 0.055f) * (1.0f / 1.055f), 2.4f);
}

// Integer texel coordinate i of an image n texels wide under a glTF wrap mode.
BP_FN bp_i32 texture_wrap(bp_i32 i, bp_i32 n, bp_u32 mode) {
  if (mode == BP_WRAP_CLAMP_TO_EDGE) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  if (mode == BP_WRAP_MIRRORED_REPEAT) {
    bp_i32 m = i % (2 * n);
    if (m < 0) m += 2 * n;
    return m < n ? m : 2 * n - 1 - m;  // period 2n, mirrored in its second half
  }
  bp_i32 m = i % n;
  return m < 0 ? m + n : m;
}

typedef struct {
  float r, g, b, a;
} Texel;

// The texel at integer coordinates (already wrapped), decoded to [0, 1] (RGB from sRGB when asked).
BP_FN Texel texture_fetch(BP_GLOBAL const bp_u32* texels, const TextureView* v, bp_i32 x, bp_i32 y) {
  bp_u32 t = texels[v->first_texel + (bp_u32)y * v->width + (bp_u32)x];
  Texel out;
  out.r = (float)(t & 255u) * (1.0f / 255.0f);
  out.g = (float)((t >> 8) & 255u) * (1.0f / 255.0f);
  out.b = (float)((t >> 16) & 255u) * (1.0f / 255.0f);
  out.a = (float)(t >> 24) * (1.0f / 255.0f);
  if (v->flags & BP_TEXTURE_SRGB) {
    out.r = srgb_to_linear(out.r);
    out.g = srgb_to_linear(out.g);
    out.b = srgb_to_linear(out.b);
  }
  return out;
}

BP_FN Texel texel_lerp(Texel a, Texel b, float t) {
  Texel out;
  out.r = a.r + (b.r - a.r) * t;
  out.g = a.g + (b.g - a.g) * t;
  out.b = a.b + (b.b - a.b) * t;
  out.a = a.a + (b.a - a.a) * t;
  return out;
}

// The filtered value at texture coordinates (u, v) (after KHR_texture_transform): texel centres at
// (i + 1/2)/width; bilinear between the four nearest centres, or the texel containing (u, v) under
// NEAREST; decoded to linear before filtering.
BP_FN Texel texture_sample(BP_GLOBAL const bp_u32* texels, const TextureView* v, float u, float t) {
  const bp_i32 w = (bp_i32)v->width, h = (bp_i32)v->height;
  const bp_u32 wrap_s = v->flags & BP_TEXTURE_WRAP_MASK;
  const bp_u32 wrap_t = (v->flags >> BP_TEXTURE_WRAP_T_SHIFT) & BP_TEXTURE_WRAP_MASK;
  // far outside [0, 1] the float coordinate loses its fraction: stay where an int holds it
  float x = clamp(u * (float)w, -1.0e9f, 1.0e9f), y = clamp(t * (float)h, -1.0e9f, 1.0e9f);
  if (v->flags & BP_TEXTURE_NEAREST)
    return texture_fetch(texels, v, texture_wrap((bp_i32)floor(x), w, wrap_s), texture_wrap((bp_i32)floor(y), h, wrap_t));
  x -= 0.5f;
  y -= 0.5f;
  float x0 = floor(x), y0 = floor(y);
  float fx = x - x0, fy = y - y0;
  bp_i32 i0 = texture_wrap((bp_i32)x0, w, wrap_s), i1 = texture_wrap((bp_i32)x0 + 1, w, wrap_s);
  bp_i32 j0 = texture_wrap((bp_i32)y0, h, wrap_t), j1 = texture_wrap((bp_i32)y0 + 1, h, wrap_t);
  Texel top = texel_lerp(texture_fetch(texels, v, i0, j0), texture_fetch(texels, v, i1, j0), fx);
  Texel bottom = texel_lerp(texture_fetch(texels, v, i0, j1), texture_fetch(texels, v, i1, j1), fx);
  return texel_lerp(top, bottom, fy);
}

// View `view` of `set` at barycentrics (b1, b2) of `triangle`: its texcoords interpolated, then
// KHR_texture_transform applied, then sampled.
BP_FN Texel texture_at(const TextureSet* set, bp_u32 view, bp_u32 triangle, float b1, float b2) {
  TextureView v = set->views[view];
  BP_GLOBAL const float* c = set->texcoords + (triangle * set->uv_slots + v.uv_slot) * 6u;
  float b0 = 1.0f - b1 - b2;
  float u = c[0] * b0 + c[2] * b1 + c[4] * b2, t = c[1] * b0 + c[3] * b1 + c[5] * b2;
  float tu = v.transform[0] * u + v.transform[2] * t + v.transform[4];
  float tv = v.transform[1] * u + v.transform[3] * t + v.transform[5];
  return texture_sample(set->texels, &v, tu, tv);
}

// A surface point's material, from the factors and the texels.
typedef struct {
  float3 base_color;      // baseColorFactor x texel (linear)
  float metallic;         // metallicFactor x B of metallicRoughnessTexture
  float roughness;        // roughnessFactor x G of metallicRoughnessTexture
  float3 emission;
  float alpha;
  int specular_textured;  // the two below come from specular textures (else the Material's hold)
  float3 dielectric_f0;   // min(f0(ior) specularColorFactor x specularColorTexture, 1)
  float specular_weight;  // specularFactor x A of specularTexture
} TexelMaterial;

// The material at barycentrics (b1, b2) of `triangle`, whose material has textures `mt`.
BP_FN TexelMaterial texel_material(const TextureSet* set, const MaterialTextures* mt, bp_u32 triangle, float b1,
                                   float b2) {
  float3 base = make_float3(mt->base_color_factor[0], mt->base_color_factor[1], mt->base_color_factor[2]);
  float alpha = mt->base_color_factor[3];
  if (mt->base_color != BP_NO_TEXTURE) {
    Texel t = texture_at(set, mt->base_color, triangle, b1, b2);
    base = base * make_float3(t.r, t.g, t.b);
    alpha *= t.a;
  }
  float metallic = mt->metallic_factor, roughness = mt->roughness_factor;
  if (mt->metallic_roughness != BP_NO_TEXTURE) {
    Texel t = texture_at(set, mt->metallic_roughness, triangle, b1, b2);
    roughness *= t.g;
    metallic *= t.b;
  }
  float3 emission = make_float3(mt->emissive_factor[0], mt->emissive_factor[1], mt->emissive_factor[2]);
  if (mt->emissive != BP_NO_TEXTURE) {
    Texel t = texture_at(set, mt->emissive, triangle, b1, b2);
    emission = emission * make_float3(t.r, t.g, t.b);
  }
  // KHR_materials_specular: specular = specularFactor x A, dielectric_f0 = min(f0(ior) x specularColor, 1)
  TexelMaterial out;
  out.specular_textured = mt->specular != BP_NO_TEXTURE || mt->specular_color != BP_NO_TEXTURE;
  out.specular_weight = mt->specular_factor;
  if (mt->specular != BP_NO_TEXTURE) out.specular_weight *= texture_at(set, mt->specular, triangle, b1, b2).a;
  float3 f0 = make_float3(mt->specular_f0[0], mt->specular_f0[1], mt->specular_f0[2]);
  if (mt->specular_color != BP_NO_TEXTURE) {
    Texel t = texture_at(set, mt->specular_color, triangle, b1, b2);
    f0 = f0 * make_float3(t.r, t.g, t.b);
  }
  out.dielectric_f0 = fmin(f0, make_float3(1.0f, 1.0f, 1.0f));
  out.base_color = base;
  out.metallic = metallic;
  out.roughness = roughness;
  out.emission = emission;
  out.alpha = alpha;
  return out;
}

// The emitted radiance at barycentrics (b1, b2) of `triangle` of `material`: factor_emission (the
// Material's) unless the material has an emissive texture.
BP_FN float3 texel_emission(const TextureSet* set, bp_u32 material, bp_u32 triangle, float b1, float b2,
                            float3 factor_emission) {
  BP_GLOBAL const MaterialTextures* mt = &set->materials[material];
  if (mt->emissive == BP_NO_TEXTURE) return factor_emission;
  Texel t = texture_at(set, mt->emissive, triangle, b1, b2);
  return make_float3(mt->emissive_factor[0] * t.r, mt->emissive_factor[1] * t.g, mt->emissive_factor[2] * t.b);
}

// alphaMode MASK: 1 where barycentrics (b1, b2) of `triangle` of `material` are a surface (alpha,
// base colour factor x texel, at or above the cutoff; always without a cutoff).
BP_FN int alpha_is_surface(const TextureSet* set, bp_u32 material, bp_u32 triangle, float b1, float b2) {
  BP_GLOBAL const MaterialTextures* mt = &set->materials[material];
  if (!(mt->alpha_cutoff > 0.0f)) return 1;
  Texel t = texture_at(set, mt->base_color, triangle, b1, b2);
  return t.a * mt->base_color_factor[3] >= mt->alpha_cutoff;
}

// True where the material's f or emission has textures (the others keep their Material as it is).
BP_FN int material_is_textured(const MaterialTextures* mt) {
  return mt->base_color != BP_NO_TEXTURE || mt->metallic_roughness != BP_NO_TEXTURE || mt->emissive != BP_NO_TEXTURE ||
         mt->specular != BP_NO_TEXTURE || mt->specular_color != BP_NO_TEXTURE;
}

// True where the material has a normalTexture (its shading normal is per texel: shared/normal_map.h).
BP_FN int material_has_normal_map(const MaterialTextures* mt) { return mt->normal != BP_NO_TEXTURE; }

#endif  // BP_SHARED_TEXTURE_H
