// Global ray-bundle iteration (docs/design.md §4) with a software transillumination buffer. One iteration:
//   rb_outgoing -> rb_emit -> scan -> rb_tile_scatter -> rb_tile_resolve -> rb_gather -> (rb_vertex -> rb_eye)
// Patch radiance is kept as E_in = L_in cos(theta_in) ("irradiance over pi"), so an element seen
// edge-on never divides by its cosine.
#include "shared/types.h"
#include "shared/bundle_types.h"
#include "shared/bundle_raster.h"
#include "shared/brdf.h"
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/rng.h"
#include "shared/surface.h"
#include "shared/weights.h"
#include "shared/lights.h"
#include "shared/textured.h"
#include "shared/alpha_mask.h"
#include "shared/through_panes.h"
#include "scan.cl"

#define BP_BACK_SIDE 0x80000000u
#define BP_NO_SENDER (-3.0e38f)  // .w of radiance that came from no patch (below any ln P)
#define BP_CONTACT (-3.2e38f)    // .w of a fragment covered by one it touches: it receives nothing, and is not counted

// The material RB reflects and emits with on `patch` (a side of an element of `material`): with
// textures its mean over the patch (host/scene/textures.h), which every weight input reads on both
// sides; uv_slots 0: the scene has no textures.
static __global const Material* rb_material(__global const Material* materials, __global const Material* patch_materials,
                                            uint uv_slots, uint material, uint patch) {
  return BP_FEATURE_TEXTURES && uv_slots > 0u && patch != BP_NO_PATCH ? &patch_materials[patch] : &materials[material];
}

// Normal of a patch (its element's normal, flipped for a back side).
static float3 patch_normal(__global const BundleElement* elements, uint patch_element) {
  __global const BundleElement* e = &elements[patch_element & ~BP_BACK_SIDE];
  float3 n = bp_load3(e->normal);
  return (patch_element & BP_BACK_SIDE) ? -n : n;
}

// The direction along +-omega that leaves a patch's side: omega or -omega, whichever is in front of n
// (also: facing(toward, n) is the normal of the side that faces `toward`).
static float3 facing(float3 n, float3 omega) { return dot(n, omega) >= 0.0f ? omega : -omega; }

// ln of the paper's P of the radiance that leaves a patch: eq. (10) for the reflected part, P = 1 for
// the emitted part, mixed by their luminance (one number per patch cannot be exact, docs/design.md §3).
static float paper_log_p_out(float3 emitted, float3 reflected, float log_p_reflected) {
  float le = emitted.x + emitted.y + emitted.z, lr = reflected.x + reflected.y + reflected.z;
  if (le + lr <= 0.0f) return log_p_reflected;
  return log_add_exp(log_or_zero(le), log_or_zero(lr) + log_p_reflected) - log(le + lr);
}

// The per-patch light sample of docs/design.md §3: one shadow ray from a random point of the patch to a
// light chosen for the patch. `irradiance` is L cos / p_solid over the rate at which patches take this
// sample (0 when the light is not reached); the techniques' weights are applied by the callers.
typedef struct {
  float3 wi;          // towards the light
  float3 irradiance;  // unweighted, over the rate
  float pdf_light;    // p_L of wi (uv)
  int is_delta;
  float select_probability;  // P(choosing the light) for this patch
  float own_samples;  // --rb-sun own: the light's samples of its own per iteration (delta_light_weights)
} PatchLightSample;

// pick: the light for the patch (forced, for a sun's own sample), or BP_NO_LIGHT to choose one.
static PatchLightSample rb_light_sample(__global const BundleElement* e, float3 n, __global const BvhNode* nodes,
                                        __global const BvhTriangle* triangles, const LightSet* light_set,
                                        uint patch, __global const Material* materials, const BundleIteration* it,
                                        Rng* rng, float ray_epsilon, __global const TriangleShading* shading,
                                        uint alpha_masks, LightPick pick) {
  PatchLightSample out;
  out.irradiance = make_float3(0.0f, 0.0f, 0.0f);
  float root = sqrt(rng_uniform(rng)), u = rng_uniform(rng);  // uniform on the element
  float3 x = bp_load3(e->v0) + bp_load3(e->e1) * (root * (1.0f - u)) + bp_load3(e->e2) * (root * u) + n * ray_epsilon;
  float u_pick = rng_uniform(rng), u1 = rng_uniform(rng), u2 = rng_uniform(rng);
  if (pick.light == BP_NO_LIGHT) pick = light_select(light_set, patch, u_pick);
  LightSample ls = light_sample_picked(light_set, materials, pick, x, u1, u2);
  out.wi = ls.wi;
  out.pdf_light = ls.pdf_uv;
  out.is_delta = ls.is_delta;
  out.select_probability = ls.select_probability;
  out.own_samples =
      it->sun_own_samples > 0u && light_set->lights[ls.light].type == BP_LIGHT_DIRECTIONAL ? (float)it->sun_own_samples : 0.0f;
  float cos_x = dot(n, ls.wi);
  if (!(cos_x > 0.0f) || ls.radiance_over_pdf.x + ls.radiance_over_pdf.y + ls.radiance_over_pdf.z <= 0.0f) return out;
  float t_max = ls.is_delta ? ls.distance : ls.distance - 4.0f * ray_epsilon;
  if (t_max <= 0.0f) return out;
  // through thin panes, attenuated (docs/design.md §11), as PT's shadow rays
  float3 through = shadow_transmittance(nodes, triangles, shading, materials, &light_set->textures, alpha_masks, x,
                                        ls.wi, t_max, ray_epsilon);
  out.irradiance = ls.radiance_over_pdf * through * (cos_x / it->light_rate);  // L cos / p_solid, over the rate
  return out;
}

// The light sample reflected towards wo, weighted as the RB light technique of the last segment (the
// product of the vertices before it is applied downstream, as for every reflection).
static float3 rb_light_reflected(const PatchLightSample* ls, const Bsdf* bsdf, float3 n, float3 wo,
                                 const BundleIteration* it) {
  if (ls->irradiance.x + ls->irradiance.y + ls->irradiance.z <= 0.0f) return make_float3(0.0f, 0.0f, 0.0f);
  BsdfValue v = bsdf_evaluate(bsdf, n, ls->wi, wo);
  float pdf_bsdf = bsdf->continuation * v.pdf_uv;
  float w = last_segment_weights(1.0f, it->weight_ratio, it->light_rate, pdf_bsdf, ls->pdf_light, ls->is_delta).rb_light;
  if (ls->own_samples > 0.0f)  // a sun that its own samples also reach (--rb-sun own)
    w = delta_light_weights(1.0f, it->weight_ratio, it->light_rate, ls->select_probability, ls->own_samples).rb_light *
        rb_delta_sample_share(ls->select_probability, ls->own_samples);
  return v.f * ls->irradiance * w;  // f L cos / p_solid, weighted
}

// 1. Outgoing radiance of every patch along the new direction: the random operator T* applied to the
//    previous incoming radiance, L_out = Le + 2 pi f(w_prev -> w_out) cos(theta_prev) L_in, with the
//    vertex's beta multiplied in on the weighted chain of --weights product (docs/design.md §3). With
//    light sampling, chain 0 leaves Le out (receivers take it through their direct chain, weighted
//    per fragment) and adds the reflected direct light and the patch's light sample instead.
__kernel void rb_outgoing(__global const BundleElement* elements, __global const uint* patch_element,
                          __global const Material* materials, __global const float4* e_in,
                          const BundleIteration it, const uint patches, __global float4* l_out,
                          __global const BvhNode* nodes, __global const BvhTriangle* triangles,
                          __global const Light* lights, __global const float* light_cdf, const uint light_seed,
                          const uint iteration, const float ray_epsilon, __global float4* eye_light,
                          __global const LightTreeNode* light_tree, __global const LightReceiver* light_receivers,
                          const uint light_selection, __global const Material* patch_materials, const uint uv_slots,
                          __global const TextureView* texture_views, __global const uint* texels,
                          __global const MaterialTextures* material_textures, __global const float* texcoords,
                          __global const TriangleShading* shading, const uint alpha_masks,
                          __global const float* environment) {
  uint p = (uint)get_global_id(0);
  if (p >= patches) return;
  uint pe = patch_element[p];
  float3 n = patch_normal(elements, pe);
  Bsdf bsdf = bsdf_from_material(rb_material(materials, patch_materials, uv_slots, elements[pe & ~BP_BACK_SIDE].material, p));
  float3 wi = facing(n, bp_private3(it.omega_prev));
  float3 wo = facing(n, bp_private3(it.omega));
  BsdfValue v = bsdf_evaluate(&bsdf, n, wi, wo);
  float3 transfer = v.f * BP_TWO_PI;  // 2 pi f, times E_in = L_in cos below
  const int light_sampling = BP_FEATURE_LIGHT_SAMPLING && it.light_count > 0u;
  const uint eye_chain = light_sampling && it.eye_direct_chain ? it.eye_direct_chain : it.chains;  // chains: none
  PatchLightSample ls;
  ls.irradiance = make_float3(0.0f, 0.0f, 0.0f);
  ls.wi = n;  // where no sample is taken: a direction rb_eye may reflect zero along
  float3 sun_reflected = make_float3(0.0f, 0.0f, 0.0f);  // --rb-sun own: the suns' own samples, weighted
  if (light_sampling) {
    Rng rng = rng_init(light_seed, p, iteration);
    LightSet light_set_ = light_set(lights, light_cdf, light_tree, light_receivers, it.light_count, light_selection);
    const TextureSet textures = {texture_views, texels, material_textures, texcoords, uv_slots};
    light_set_.textures = textures;  // emissive textures at the sampled point
    light_set_.environment = environment_map(environment, it.environment_width, it.environment_height);
    // a black patch reflects no light sample; the others take one at the rate it.light_rate
    if (bsdf.continuation > 0.0f && (it.light_rate >= 1.0f || rng_uniform(&rng) < it.light_rate)) {
      __global const BundleElement* element = &elements[pe & ~BP_BACK_SIDE];
      LightPick choose = {BP_NO_LIGHT, 0.0f};
      ls = rb_light_sample(element, n, nodes, triangles, &light_set_, p, materials, &it, &rng, ray_epsilon, shading,
                           alpha_masks, choose);
      // and one of each directional light, whichever was chosen (the lights' list ends with them)
      for (uint l = it.light_count; it.sun_own_samples > 0u && l-- > 0u && light_is_infinite(lights[l].type);) {
        if (lights[l].type != BP_LIGHT_DIRECTIONAL) continue;
        LightPick sun = {l, light_select_probability(&light_set_, p, l)};
        PatchLightSample own = rb_light_sample(element, n, nodes, triangles, &light_set_, p, materials, &it, &rng,
                                               ray_epsilon, shading, alpha_masks, sun);
        sun_reflected += rb_light_reflected(&own, &bsdf, n, wo, &it);
      }
    }
  }
  if (eye_chain < it.chains) {
    // The same sample for the eye vertex (--eye-direct shared): its irradiance weighted as the RB
    // light technique of the eye vertex's last segment, and its direction, for rb_eye to reflect.
    float w = ls.irradiance.x + ls.irradiance.y + ls.irradiance.z > 0.0f
                  ? eye_segment_weights(it.weight_ratio, it.light_rate,
                                        eye_direct_material_proxy_pdf_uv(&materials[elements[pe & ~BP_BACK_SIDE].material],
                                                                         dot(n, ls.wi)),
                                        0.0f, ls.pdf_light, ls.is_delta).rb_light
                  : 0.0f;
    eye_light[2 * p] = (float4)(ls.irradiance.x * w, ls.irradiance.y * w, ls.irradiance.z * w, 0.0f);
    // rb_eye reflects the interpolated irradiance of the patches around a pixel along this direction:
    // where this patch's own sample brought nothing (blocked, not taken, or a light edge-on), along the
    // normal, so the neighbours' light is not lost to a zero BRDF (exact for Lambert either way).
    float3 dir = w > 0.0f ? ls.wi : n;
    eye_light[2 * p + 1] = (float4)(dir.x, dir.y, dir.z, 0.0f);
  }
  for (uint c = 0; c < it.chains; ++c) {
    float4 e = e_in[p * it.chains + c];
    float3 reflected = transfer * make_float3(e.x, e.y, e.z);
    float3 emitted = bsdf.emission;
    float w = 0.0f;
    if (c == 0 && it.weight_mode == BP_WEIGHTS_PRODUCT)
      reflected *= vertex_beta(bsdf.continuation, v.pdf_uv, it.weight_ratio, it.beta_heuristic);
    if (c == 0 && it.weight_mode == BP_WEIGHTS_PAPER)
      w = paper_log_pstar_step(bsdf.continuation, v.pdf_uv, e.w);  // (10)
    if (c == 0 && light_sampling) {
      float4 direct = e_in[p * it.chains + it.direct_chain];  // already weighted per fragment
      reflected += transfer * make_float3(direct.x, direct.y, direct.z) + rb_light_reflected(&ls, &bsdf, n, wo, &it) +
                   sun_reflected;
      emitted = make_float3(0.0f, 0.0f, 0.0f);
    }
    if (light_sampling && (c == it.direct_chain || c == eye_chain))
      emitted = reflected = make_float3(0.0f, 0.0f, 0.0f);  // unused: direct chains are received from Le
    if (c == 0 && it.weight_mode == BP_WEIGHTS_PAPER) w = paper_log_p_out(emitted, reflected, w);
    float3 l = emitted + reflected;
    l_out[p * it.chains + c] = (float4)(l.x, l.y, l.z, w);
  }
}

// 2. Fragments (tile key, depth) of each element, rasterized once into the element's own slots
//    [slot_start[e], slot_start[e + 1]) (raster_fragment_bound: never more; the loop stops there all
//    the same), their number, and the fragments per tile. The key packs the bin as its 16x16 tile and
//    its place in the tile: tile << 8 | local bin.
__kernel void rb_emit(__global const BundleElement* elements, const BundleIteration it, const uint count,
                      __global const uint* slot_start, __global uint* fragment_counts, __global uint* fragment_key,
                      __global float* fragment_depth, __global uint* tile_counts, const uint alpha_masks,
                      __global const uint* element_triangle, __global const TriangleShading* shading,
                      __global const TextureView* texture_views, __global const uint* texels,
                      __global const MaterialTextures* material_textures, __global const float* texcoords,
                      const uint uv_slots) {
  uint e = (uint)get_global_id(0);
  if (e >= count) return;
  RasterElement r = raster_setup(&elements[e], &it);
  // alphaMode MASK: a bin whose centre falls where the element is cut away gets no fragment
  const TextureSet textures = {texture_views, texels, material_textures, texcoords, uv_slots};
  uint masked_triangle = BP_NO_PATCH, material = elements[e].material;
  float c1[3], c2[3];  // the element's corners on its triangle
  if (BP_FEATURE_TEXTURES && alpha_masks && material_textures[material].alpha_cutoff > 0.0f) {
    masked_triangle = element_triangle[e];
    __global const TriangleShading* t = &shading[masked_triangle];
    patch_corner_barycentrics(e - t->first_element, t->patch_subdiv, c1, c2);
  }
  const uint begin = slot_start[e], end = slot_start[e + 1];
  uint slot = begin, tile = 0u, in_tile = 0u;  // a run of fragments in one tile: one atomic for the run
  for (int j = r.j0; j <= r.j1 && slot < end; ++j) {
    int first, last;
    raster_row_span(&r, j, &first, &last);
    for (int i = first; i <= last && slot < end; ++i) {
      if (masked_triangle != BP_NO_PATCH) {
        // the bin centre's barycentrics in the element (edge functions over twice the area), then on its triangle
        float px = (float)i + 0.5f, py = (float)j + 0.5f, scale = r.inv_double_area * r.orientation;
        float l1 = (r.slope[1] * px + r.rise[1] * py + r.base[1]) * scale;
        float l2 = (r.slope[2] * px + r.rise[2] * py + r.base[2]) * scale, l0 = 1.0f - l1 - l2;
        float b1 = c1[0] * l0 + c1[1] * l1 + c1[2] * l2, b2 = c2[0] * l0 + c2[1] * l1 + c2[2] * l2;
        if (!alpha_is_surface(&textures, material, masked_triangle, b1, b2)) continue;
      }
      uint key = bundle_tile_key((uint)i, (uint)j, it.bins_per_side);
      fragment_key[slot] = key;
      fragment_depth[slot] = raster_depth(&r, i, j);
      if (key >> BP_TILE_LOCAL_BITS != tile && in_tile > 0u) {
        atomic_add(&tile_counts[tile], in_tile);
        in_tile = 0u;
      }
      tile = key >> BP_TILE_LOCAL_BITS;
      ++in_tile;
      ++slot;
    }
  }
  if (in_tile > 0u) atomic_add(&tile_counts[tile], in_tile);
  fragment_counts[e] = slot - begin;
}

// 3. Counting sort by tile, after the scan of the tile counts: each element places its fragments in
//    their tiles' ranges, with depth, element and local bin next to the tile's other fragments so a
//    tile is resolved from one contiguous range, and remembers where each went (tiled_at). Taking the
//    places by counting the tile counts down leaves them at 0 for the next iteration's emit.
__kernel void rb_tile_scatter(__global const uint* slot_start, __global const uint* fragment_counts,
                              __global const uint* fragment_key, __global const float* fragment_depth,
                              const uint count, __global const uint* tile_start, __global uint* tile_counts,
                              __global uint* tiled_at, __global uint* tiled_local, __global float* tiled_depth,
                              __global uint* tiled_element) {
  uint e = (uint)get_global_id(0);
  if (e >= count) return;
  const uint begin = slot_start[e], end = begin + fragment_counts[e];
  for (uint run = begin; run < end;) {  // a run of fragments in one tile takes its places with one atomic
    const uint tile = fragment_key[run] >> BP_TILE_LOCAL_BITS;
    uint run_end = run + 1u;
    while (run_end < end && fragment_key[run_end] >> BP_TILE_LOCAL_BITS == tile) ++run_end;
    uint at = tile_start[tile] + atomic_sub(&tile_counts[tile], run_end - run) - (run_end - run);
    for (uint s = run; s < run_end; ++s, ++at) {
      tiled_at[s] = at;
      tiled_local[at] = fragment_key[s] & (BP_TILE_BINS - 1u);
      tiled_depth[at] = fragment_depth[s];
      tiled_element[at] = e;
    }
    run = run_end;
  }
}

// Depth order within a bin; ties (touching elements) broken by element index so the order, and
// so the image, does not depend on the scatter's race.
static int fragment_before(__global const float* depth, __global const uint* element, uint a, uint b) {
  float da = depth[a], db = depth[b];
  return da < db || (da == db && element[a] < element[b]);
}

// The sides of an element as seen along omega: the patch facing -omega (towards smaller depth) and
// the one facing +omega; BP_NO_PATCH for the black back of a single-sided surface.
static void sides_along(__global const BundleElement* e, float3 omega, uint* minus_patch, uint* plus_patch) {
  int front_faces_minus = dot(bp_load3(e->normal), omega) < 0.0f;
  *minus_patch = front_faces_minus ? e->front_patch : e->back_patch;
  *plus_patch = front_faces_minus ? e->back_patch : e->front_patch;
}

// Light straight from an emitter, as a direct chain of a receiving patch takes it: the sender's Le
// weighted as the RB bundle technique of the last segment (docs/design.md §3). The light travels along
// `travel` over `distance` (the fragments' depth difference) from the sender element to the
// receiver's side with normal n_receiver. For the direct chain the receiver will send it along
// omega_next (PT's density of that pair); for the eye chain (eye_vertex) the eye sees the receiver,
// and the view-independent proxy stands in for PT's density.
// The patches: the sender's emitting side, the receiver's receiving side (light selection's receiver).
static float4 rb_direct_received(__global const BundleElement* elements, __global const Material* materials,
                                 __global const Material* patch_materials, uint uv_slots,
                                 uint sender_element, uint receiver_element, float3 n_receiver, float3 travel,
                                 float distance, int eye_vertex, const BundleIteration* it, const LightSet* light_set,
                                 uint sender_patch, uint receiver_patch) {
  __global const BundleElement* se = &elements[sender_element];
  __global const Material* sm = rb_material(materials, patch_materials, uv_slots, se->material, sender_patch);
  float3 le = bp_load3(sm->emission);
  if (le.x + le.y + le.z <= 0.0f) return (float4)(0.0f);
  float p_light = light_pdf_uv_area(light_pdf_area_from(light_set, materials, receiver_patch, sender_patch, se->material),
                                    distance, fabs(dot(bp_load3(se->normal), travel)));
  float3 wi = facing(n_receiver, travel);
  float w;
  if (eye_vertex) {
    float proxy = eye_direct_material_proxy_pdf_uv(&materials[elements[receiver_element].material], dot(n_receiver, wi));
    w = eye_segment_weights(it->weight_ratio, it->light_rate, proxy, 0.0f, p_light, 0).rb_bundle;
  } else {
    Bsdf receiver = bsdf_from_material(
        rb_material(materials, patch_materials, uv_slots, elements[receiver_element].material, receiver_patch));
    float3 wo = facing(n_receiver, bp_private3(it->omega_next));
    float pdf_bsdf = receiver.continuation * bsdf_pdf_uv(&receiver, n_receiver, wi, wo);
    w = last_segment_weights(1.0f, it->weight_ratio, it->light_rate, pdf_bsdf, p_light, 0).rb_bundle;
  }
  return (float4)(le.x * w, le.y * w, le.z * w, 0.0f);
}

// The environment (--environment) as a patch receives it where no fragment is in front, the light
// travelling along `travel`: for the direct chains weighted as the RB bundle technique of the last
// segment with the environment light's p_L of -travel from the receiving patch (the number PT's BSDF
// samples and the light samples use), like rb_direct_received; for chain 0 with light sampling
// nothing (it leaves light straight from emitters to the direct chain); for the others the radiance
// itself, with the paper's P = 1 of an emitter (.w = ln 1).
static float4 rb_environment_received(__global const BundleElement* elements, __global const Material* materials,
                                      __global const Material* patch_materials, uint uv_slots, uint receiver_patch,
                                      uint receiver_element, float3 n_receiver, float3 travel, uint c, uint direct,
                                      uint eye, int light_sampling, const BundleIteration* it,
                                      const LightSet* light_set) {
  if (c == 0u && light_sampling) return (float4)(0.0f, 0.0f, 0.0f, BP_NO_SENDER);
  float3 env = environment_radiance(&light_set->environment, -travel);
  if (c != direct && c != eye) return (float4)(env.x, env.y, env.z, 0.0f);
  // the back of a one-sided element has no patch to receive it (nor to choose lights for)
  if (env.x + env.y + env.z <= 0.0f || receiver_patch == BP_NO_PATCH) return (float4)(0.0f);
  float3 wi = facing(n_receiver, travel);
  float p_light = light_pdf_uv_environment(light_set, receiver_patch, it->environment_light, -travel);
  float w;
  if (c == eye) {
    float proxy = eye_direct_material_proxy_pdf_uv(&materials[elements[receiver_element].material], dot(n_receiver, wi));
    w = eye_segment_weights(it->weight_ratio, it->light_rate, proxy, 0.0f, p_light, 0).rb_bundle;
  } else {
    Bsdf receiver = bsdf_from_material(
        rb_material(materials, patch_materials, uv_slots, elements[receiver_element].material, receiver_patch));
    float3 wo = facing(n_receiver, bp_private3(it->omega_next));
    float pdf_bsdf = receiver.continuation * bsdf_pdf_uv(&receiver, n_receiver, wi, wo);
    w = last_segment_weights(1.0f, it->weight_ratio, it->light_rate, pdf_bsdf, p_light, 0).rb_bundle;
  }
  return (float4)(env.x * w, env.y * w, env.z * w, 0.0f);
}

// Whether an element is (partly) a thin pane, which passes bundles straight through (docs/design.md §11).
static int rb_is_pane(__global const BundleElement* elements, __global const Material* materials, uint element) {
  return BP_FEATURE_TRANSMISSION && (materials[elements[element].material].flags & BP_MATERIAL_THIN_TRANSMITTER);
}

// What the fragment at place a of a bin's depth order [first, last) receives in chain c when its
// neighbour at a + step is a thin pane (docs/design.md §11: a filter on the segment, not a vertex): the
// light travels along `travel` (+omega from the fragments before a, step -1; -omega from those after,
// step +1) to the receiving patch (its side with normal n_receiver). The pane's own outgoing radiance
// (its opaque rest), plus through it, times its transmittance along omega, what arrives at the pane
// from beyond, found the same way, up to an opaque sender, a contact, or the end of the bin (the
// environment). Each sender weighted as the plain transfer weighs it (rb_direct_received at the
// distance from a). .w (the paper's ln P): the brightest part's.
static float4 rb_received_through_panes(__global const BundleElement* elements, __global const Material* materials,
                                        __global const Material* patch_materials, uint uv_slots,
                                        __global const uint* tile_order, __global const uint* tiled_element,
                                        __global const float* tiled_depth, __global const float4* l_out,
                                        const BundleIteration* it, const LightSet* light_set, uint first, uint last,
                                        uint a, int step, uint c, uint direct, uint eye, int light_sampling,
                                        int environment, uint receiver_patch, uint receiver_element,
                                        float3 n_receiver, float3 travel) {
  const float3 omega = bp_private3(it->omega);
  const float depth_a = tiled_depth[tile_order[a]];
  float3 sum = make_float3(0.0f, 0.0f, 0.0f), through = make_float3(1.0f, 1.0f, 1.0f);
  float w = BP_NO_SENDER, brightest = -1.0f;
  uint k = a;
  for (uint crossings = 0u; crossings <= BP_MAX_PANE_CROSSINGS; ++crossings) {
    float4 r = (float4)(0.0f, 0.0f, 0.0f, BP_NO_SENDER);
    const int end = step < 0 ? k == first : k + 1u == last;
    if (end && environment)  // nothing beyond: the environment
      r = rb_environment_received(elements, materials, patch_materials, uv_slots, receiver_patch, receiver_element,
                                  n_receiver, travel, c, direct, eye, light_sampling, it, light_set);
    uint next = 0u, element = 0u;
    float depth = 0.0f;
    if (!end) {
      next = step < 0 ? k - 1u : k + 1u;
      element = tiled_element[tile_order[next]];
      depth = tiled_depth[tile_order[next]];
      // a pane touching the next fragment is covered on that side: nothing comes through it
      if (k != a && fabs(depth - tiled_depth[tile_order[k]]) < it->contact_depth) break;
      uint minus_side, plus_side;
      sides_along(&elements[element], omega, &minus_side, &plus_side);
      const uint sender = step < 0 ? plus_side : minus_side;  // the side facing the receiver
      if (sender != BP_NO_PATCH && (c == direct || c == eye) && receiver_patch != BP_NO_PATCH)
        r = rb_direct_received(elements, materials, patch_materials, uv_slots, element, receiver_element, n_receiver,
                               travel, fabs(depth_a - depth), c == eye, it, light_set, sender, receiver_patch);
      else if (sender != BP_NO_PATCH && c != direct && c != eye)
        r = l_out[sender * it->chains + c];
    }
    float3 part = through * make_float3(r.x, r.y, r.z);
    float brightness = part.x + part.y + part.z;
    if (brightness > brightest) {
      brightest = brightness;
      w = r.w;
    }
    sum += part;
    if (end || !rb_is_pane(elements, materials, element)) break;
    through *= pane_optics(&materials[elements[element].material], dot(bp_load3(elements[element].normal), omega))
                   .transmittance;
    if (through.x + through.y + through.z <= 0.0f) break;
    k = next;
  }
  return (float4)(sum.x, sum.y, sum.z, w);
}

// 4. Resolve one tile: counting sort of its fragments by bin (private counters), depth sort per bin,
//    then the transfer: consecutive fragments exchange radiance. The side of a fragment facing
//    -omega receives what the previous fragment sends along +omega, the other side what the next
//    one sends along -omega; nothing in front: the (black) background.
__kernel void rb_tile_resolve(__global const BundleElement* elements, __global const Material* materials,
                              __global const uint* tile_start, __global const uint* tiled_local,
                              __global const float* tiled_depth, __global const uint* tiled_element,
                              __global uint* tile_order, __global const float4* l_out, const BundleIteration it,
                              const uint tiles, __global float4* received_minus, __global float4* received_plus,
                              __global ulong* fragment_total, __global const Light* lights,
                              __global const float* light_cdf, __global const LightTreeNode* light_tree,
                              __global const LightReceiver* light_receivers, const uint light_selection,
                              __global const Material* patch_materials, const uint uv_slots,
                              __global const float* environment_texels) {
  uint tile = (uint)get_global_id(0);
  if (tile == 0u) *fragment_total += tile_start[tiles];  // for the statistics, read back with the image sums
  if (tile >= tiles) return;
  uint begin = tile_start[tile], end = tile_start[tile + 1];
  if (begin == end) return;
  uint bin_start[BP_TILE_BINS + 1];
  for (uint b = 0; b <= BP_TILE_BINS; ++b) bin_start[b] = 0u;
  for (uint a = begin; a < end; ++a) bin_start[tiled_local[a] + 1u] += 1u;
  for (uint b = 0; b < BP_TILE_BINS; ++b) bin_start[b + 1] += bin_start[b];
  uint cursor[BP_TILE_BINS];
  for (uint b = 0; b < BP_TILE_BINS; ++b) cursor[b] = bin_start[b];
  for (uint a = begin; a < end; ++a) tile_order[begin + cursor[tiled_local[a]]++] = a;

  const float3 omega = bp_private3(it.omega);
  const float4 nothing = (float4)(0.0f, 0.0f, 0.0f, BP_NO_SENDER);  // black, and no P
  const int light_sampling = BP_FEATURE_LIGHT_SAMPLING && it.light_count > 0u;
  const uint chains = it.chains, direct = light_sampling ? it.direct_chain : chains;  // chains: none
  const uint eye = light_sampling && it.eye_direct_chain ? it.eye_direct_chain : chains;
  LightSet light_set_ = light_set(lights, light_cdf, light_tree, light_receivers, it.light_count, light_selection);
  light_set_.environment = environment_map(environment_texels, it.environment_width, it.environment_height);
  const int environment = light_set_.environment.width > 0u;
  for (uint b = 0; b < BP_TILE_BINS; ++b) {
    uint first = begin + bin_start[b], last = begin + bin_start[b + 1];
    if (first == last) continue;
    for (uint a = first + 1; a < last; ++a) {  // insertion sort: lists are the scene's depth complexity
      uint x = tile_order[a], c = a;
      while (c > first && fragment_before(tiled_depth, tiled_element, x, tile_order[c - 1])) {
        tile_order[c] = tile_order[c - 1];
        --c;
      }
      tile_order[c] = x;
    }
    // The patch whose radiance arrives along +omega at the current fragment, its element and depth.
    uint sender = BP_NO_PATCH, sender_element = 0u;
    float sender_depth = 0.0f;
    uint minus_patch, plus_patch;
    sides_along(&elements[tiled_element[tile_order[first]]], omega, &minus_patch, &plus_patch);
    for (uint a = first; a < last; ++a) {
      uint fragment = tile_order[a], element = tiled_element[fragment];
      float depth = tiled_depth[fragment];
      float3 n = bp_load3(elements[element].normal);
      const int touches_sender = a > first && depth - sender_depth < it.contact_depth;
      for (uint c = 0; c < chains; ++c) {
        float4 r = nothing;
        if (touches_sender)
          r.w = BP_CONTACT;
        else if (a > first && rb_is_pane(elements, materials, sender_element))
          r = rb_received_through_panes(elements, materials, patch_materials, uv_slots, tile_order, tiled_element,
                                        tiled_depth, l_out, &it, &light_set_, first, last, a, -1, c, direct, eye,
                                        light_sampling, environment, minus_patch, element, facing(-omega, n), omega);
        else if (environment && a == first)  // nothing in front along -omega: the environment
          r = rb_environment_received(elements, materials, patch_materials, uv_slots, minus_patch, element,
                                      facing(-omega, n), omega, c, direct, eye,
                                      light_sampling, &it, &light_set_);
        else if (sender != BP_NO_PATCH && (c == direct || c == eye) && minus_patch != BP_NO_PATCH)
          r = rb_direct_received(elements, materials, patch_materials, uv_slots, sender_element, element,
                                 facing(-omega, n), omega,
                                 depth - sender_depth, c == eye, &it, &light_set_, sender, minus_patch);
        else if (sender != BP_NO_PATCH && c != direct && c != eye)
          r = l_out[sender * chains + c];
        received_minus[fragment * chains + c] = r;
      }
      const uint own_plus = plus_patch;
      sender = plus_patch;
      sender_element = element;
      sender_depth = depth;
      uint next_minus = BP_NO_PATCH, next_element = 0u;
      float next_depth = 0.0f;
      if (a + 1 < last) {
        uint next = tile_order[a + 1];
        next_element = tiled_element[next];
        next_depth = tiled_depth[next];
        sides_along(&elements[next_element], omega, &minus_patch, &plus_patch);
        next_minus = minus_patch;
      }
      const int touches_next = a + 1 < last && next_depth - depth < it.contact_depth;
      for (uint c = 0; c < chains; ++c) {
        float4 r = nothing;
        if (touches_next)
          r.w = BP_CONTACT;
        else if (a + 1 < last && rb_is_pane(elements, materials, next_element))
          r = rb_received_through_panes(elements, materials, patch_materials, uv_slots, tile_order, tiled_element,
                                        tiled_depth, l_out, &it, &light_set_, first, last, a, 1, c, direct, eye,
                                        light_sampling, environment, own_plus, element, facing(omega, n), -omega);
        else if (environment && a + 1 == last)  // nothing in front along +omega: the environment
          r = rb_environment_received(elements, materials, patch_materials, uv_slots, own_plus, element,
                                      facing(omega, n), -omega, c, direct, eye,
                                      light_sampling, &it, &light_set_);
        else if (next_minus != BP_NO_PATCH && (c == direct || c == eye) && own_plus != BP_NO_PATCH)
          r = rb_direct_received(elements, materials, patch_materials, uv_slots, next_element, element,
                                 facing(omega, n), -omega,
                                 next_depth - depth, c == eye, &it, &light_set_, next_minus, own_plus);
        else if (next_minus != BP_NO_PATCH && c != direct && c != eye)
          r = l_out[next_minus * chains + c];
        received_plus[fragment * chains + c] = r;
      }
    }
  }
}

// Sum over an element's fragments (slots begin..end, resolved at tiled_at) of one chain's received
// radiance. With with_p, .w becomes ln of the mean P of the fragments that had a sender (the paper's
// area-weighted mean over senders).
static float4 gather_chain(__global const float4* received, __global const uint* tiled_at, uint begin, uint end,
                           uint chains, uint c, float scale, int with_p) {
  float3 sum = make_float3(0.0f, 0.0f, 0.0f);
  float log_p_sum = BP_LOG_ZERO, senders = 0.0f;
  uint open = 0u;
  for (uint s = begin; s < end; ++s) {
    float4 r = received[tiled_at[s] * chains + c];
    if (r.w == BP_CONTACT) continue;
    ++open;
    sum += make_float3(r.x, r.y, r.z);
    if (with_p && r.w > BP_NO_SENDER) {
      log_p_sum = log_add_exp(log_p_sum, r.w);  // log-sum-exp: P passes 1e38 on long glossy paths
      senders += 1.0f;
    }
  }
  // The mean over the fragments nothing touches stands for the whole element's: the part covered by a
  // touching surface is never seen, so it must not darken the rest.
  sum *= open > 0u ? scale * (float)(end - begin) / (float)open : 0.0f;
  return (float4)(sum.x, sum.y, sum.z, senders > 0.0f ? log_p_sum - log(senders) : 0.0f);
}

// 5. New incoming radiance per patch: transferred power over area. With n_bins covered,
//    E[n_bins] = A |cos theta| / A_bin, so E_in = sum L_out * A_bin / A estimates L_in cos theta.
__kernel void rb_gather(__global const BundleElement* elements, __global const uint* slot_start,
                        __global const uint* fragment_counts, __global const uint* tiled_at,
                        __global const float4* received_minus, __global const float4* received_plus,
                        const BundleIteration it, const uint count, __global float4* e_in, const uint alpha_masks,
                        __global const float* element_coverage) {
  uint e = (uint)get_global_id(0);
  if (e >= count) return;
  __global const BundleElement* el = &elements[e];
  uint begin = slot_start[e], end = begin + fragment_counts[e];
  float scale = it.bin_size * it.bin_size / el->area;
  // alphaMode MASK: the power arrives on the part that is there, E_in is over that part's area
  if (BP_FEATURE_TEXTURES && alpha_masks && element_coverage[e] > 0.0f) scale /= element_coverage[e];
  uint minus_patch, plus_patch;
  sides_along(el, bp_private3(it.omega), &minus_patch, &plus_patch);
  const int with_p = it.weight_mode == BP_WEIGHTS_PAPER;
  for (uint c = 0; c < it.chains; ++c) {
    if (minus_patch != BP_NO_PATCH)
      e_in[minus_patch * it.chains + c] =
          gather_chain(received_minus, tiled_at, begin, end, it.chains, c, scale, with_p);
    if (plus_patch != BP_NO_PATCH)
      e_in[plus_patch * it.chains + c] = gather_chain(received_plus, tiled_at, begin, end, it.chains, c, scale, with_p);
  }
}

// Primary hits for the eye estimate, jittered within the pixel like the path tracer's.
__kernel void rb_eye_hits(__global const BvhNode* nodes, __global const BvhTriangle* triangles,
                          __global const TriangleShading* shading, __global const Material* materials,
                          const CameraParams camera, const uint seed, const uint jitter_index,
                          __global EyeHit* hits, __global const float* shading_normals, const uint has_normals,
                          __global float4* eye_normals, const uint uv_slots, __global const TextureView* texture_views,
                          __global const uint* texels, __global const MaterialTextures* material_textures,
                          __global const float* texcoords, __global float4* eye_texels, const uint alpha_masks,
                          const float ray_epsilon, __global const float* tangents,
                          __global const ClusterFan* cluster_fans) {
  uint pixel = (uint)get_global_id(0);
  if (pixel >= camera.width * camera.height) return;
  Rng rng = rng_init(seed, pixel, jitter_index);
  float jx = rng_uniform(&rng), jy = rng_uniform(&rng);
  float3 origin = make_float3(camera.position[0], camera.position[1], camera.position[2]);
  float3 dir = camera_ray_direction(&camera, pixel % camera.width, pixel / camera.width, jx, jy);
  EyeHit out;
  out.patch = BP_NO_PATCH;
  out.element = BP_NO_PATCH;  // the ray leaves the scene: it sees the environment
  out.l1 = out.l2 = 0.0f;
  out.wo[0] = -dir.x; out.wo[1] = -dir.y; out.wo[2] = -dir.z;
  out.pad0 = out.pad1 = 0.0f;
  Hit hit;
  float3 shading_normal = make_float3(0.0f, 0.0f, 1.0f);
  // the texel's base colour (.w metallic), roughness (.y: 1 where specular is textured, .w: 1, 0
  // untextured), emission, and dielectric f0 (.w specular)
  float4 texel_base = (float4)(0.0f), texel_roughness = (float4)(0.0f), texel_emission = (float4)(0.0f);
  float4 texel_specular = (float4)(0.0f);
  const TextureSet textures = {texture_views, texels, material_textures, texcoords, uv_slots};
  // through thin panes (docs/design.md §11): the eye sees what is behind a pane, attenuated, or the pane's
  // opaque rest; never its mirror, which is PT's alone
  float3 filter = make_float3(1.0f, 1.0f, 1.0f);
  uint pane_event, rays = 0u;
  const int hits_surface = closest_hit_through_panes(nodes, triangles, shading, materials, &textures, alpha_masks,
                                                     origin, dir, ray_epsilon, 0, &rng, &filter, &pane_event, &hit, &rays);
  out.filter[0] = filter.x; out.filter[1] = filter.y; out.filter[2] = filter.z;
  if (hits_surface) {
    const float3 position = origin + dir * hit.t;
    SurfaceHit s = surface_at_shaded(shading, cluster_fans, shading_normals, has_normals, &textures, tangents,
                                     hit.triangle, hit.b1, hit.b2, position, dir);
    shading_normal = s.shading_normal;
    out.element = 0u;
    if (s.reflects || (materials[s.material].flags & BP_MATERIAL_DOUBLE_SIDED)) {
      const PatchPlace place = patch_place(&shading[hit.triangle], cluster_fans, hit.b1, hit.b2, position);
      out.patch = s.patch;
      out.element = place.first_element + patch_local_index(place.b1, place.b2, place.patch_subdiv);
      patch_local_barycentrics(place.b1, place.b2, place.patch_subdiv, &out.l1, &out.l2);
      MaterialTextures mt;
      if (BP_FEATURE_TEXTURES && uv_slots > 0u && material_is_textured((mt = material_textures[s.material], &mt))) {
        // the eye gather reflects with the texel at the hit (docs/design.md §6), its weights with the patch's mean
        TexelMaterial tm = texel_material(&textures, &mt, hit.triangle, hit.b1, hit.b2);
        texel_base = (float4)(tm.base_color.x, tm.base_color.y, tm.base_color.z, tm.metallic);
        texel_roughness = (float4)(tm.roughness, tm.specular_textured ? 1.0f : 0.0f, 0.0f, 1.0f);
        texel_emission = (float4)(tm.emission.x, tm.emission.y, tm.emission.z, 0.0f);
        texel_specular = (float4)(tm.dielectric_f0.x, tm.dielectric_f0.y, tm.dielectric_f0.z, tm.specular_weight);
      }
    }
  }
  hits[pixel] = out;
  if (BP_FEATURE_TEXTURES && uv_slots > 0u) {
    eye_texels[BP_EYE_TEXELS * pixel] = texel_base;
    eye_texels[BP_EYE_TEXELS * pixel + 1] = texel_roughness;
    eye_texels[BP_EYE_TEXELS * pixel + 2] = texel_emission;
    eye_texels[BP_EYE_TEXELS * pixel + 3] = texel_specular;
  }
  if (BP_FEATURE_SHADING_NORMALS && has_normals)
    eye_normals[pixel] = (float4)(shading_normal.x, shading_normal.y, shading_normal.z, 0.0f);
}

// What the eye vertex reflects of incoming irradiance E_in = L_in cos(theta_patch) arriving along wi,
// per unit E_in and solid angle: f(wi, wo) cos(theta_shading) / cos(theta_patch), the BRDF and cosine
// about the shading normal (docs/design.md §6); with the flat normal, f (flat: about the patch normal).
// A direction below the shading normal reflects nothing.
static float3 eye_brdf(const Bsdf* bsdf, float3 n_patch, float3 n_shading, float3 wi, float3 wo, float3 flat_f) {
  float3 d = n_shading - n_patch;
  if (!BP_FEATURE_SHADING_NORMALS || (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f)) return flat_f;
  float cos_patch = dot(n_patch, wi), cos_shading = dot(n_shading, wi);
  if (!(cos_patch > 1e-6f) || !(cos_shading > 0.0f)) return make_float3(0.0f, 0.0f, 0.0f);
  return bsdf_eval(bsdf, n_shading, wi, wo) * (cos_shading / cos_patch);
}

// Values per patch that the eye estimate interpolates: every chain, and with --eye-direct shared the
// patches' light samples for the eye (eye_light) in one slot more.
static uint eye_slots(const BundleIteration* it) {
  return it->chains + (BP_FEATURE_LIGHT_SAMPLING && it->light_count > 0u && it->eye_direct_chain ? 1u : 0u);
}

// Gouraud vertices: the area-weighted mean E_in (every chain, P too, and the eye's light samples) of
// the patches around each welded corner.
__kernel void rb_vertex(__global const uint* vertex_patch_start, __global const uint* vertex_patches,
                        __global const BundleElement* elements, __global const uint* patch_element,
                        __global const float4* e_in, const BundleIteration it, const uint vertices,
                        __global float4* e_vertex, __global const float4* eye_light, const uint alpha_masks,
                        __global const float* element_coverage) {
  uint v = (uint)get_global_id(0);
  if (v >= vertices) return;
  const uint slots = eye_slots(&it);
  for (uint c = 0; c < slots; ++c) {
    float4 sum = (float4)(0.0f);
    float area = 0.0f;
    for (uint k = vertex_patch_start[v]; k < vertex_patch_start[v + 1]; ++k) {
      uint p = vertex_patches[k];
      const uint element = patch_element[p] & ~BP_BACK_SIDE;
      float a = elements[element].area;
      if (BP_FEATURE_TEXTURES && alpha_masks) a *= element_coverage[element];  // alpha MASK: the part that is there
      sum += (c < it.chains ? e_in[p * it.chains + c] : eye_light[2 * p]) * a;
      area += a;
    }
    e_vertex[v * slots + c] = area > 0.0f ? sum / area : (float4)(0.0f);
  }
}

// One interpolated value at an eye hit: the patch's own (*flat) or interpolated from its corners'
// `slot` (Gouraud; *flat is then not read).
static float4 eye_irradiance(const EyeHit* h, __global const float4* flat, __global const uint* patch_vertices,
                             __global const float4* e_vertex, uint gouraud, uint slots, uint slot) {
  if (!gouraud) return *flat;
  __global const uint* pv = &patch_vertices[3 * h->patch];
  return e_vertex[pv[0] * slots + slot] * (1.0f - h->l1 - h->l2) + e_vertex[pv[1] * slots + slot] * h->l1 +
         e_vertex[pv[2] * slots + slot] * h->l2;
}

// Whether a pixel's eye estimate is gathered once per block of iterations (rb_eye_patches,
// rb_eye_block) rather than every iteration (rb_eye): with eye_blocks on, every pixel that sees the
// environment, and every Lambert eye vertex without a shading normal of its own. There f(wi, wo) is
// kd/pi (0 behind the patch), the same every iteration (not for glTF's metallic-roughness BRDF, whose
// Fresnel makes even its diffuse part depend on omega and wo), and everything else the estimate reads --
// the interpolated E_in, the weights, the light samples' directions -- depends on the patch, its
// corners and omega alone, so the block's sum of estimates is f times the sum of those per-patch
// terms (docs/design.md §8: the per-iteration gather is linear in the patch irradiance). Not with the
// paper's weights (their ln P at the eye is not linear in E_in).
static int eye_in_blocks(uint eye_blocks, const Bsdf* bsdf, float3 n, float3 ns) {
  if (!eye_blocks) return 0;
  if (BP_FEATURE_PHONG && bsdf->p_diffuse < 1.0f) return 0;  // a Phong lobe: f depends on omega and wo
  if (bsdf_is_ggx(bsdf)) return 0;
  float3 d = ns - n;
  return !BP_FEATURE_SHADING_NORMALS || (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f);
}

// The eye vertex of a hit on a patch: its BSDF (the patch's material, whose weight inputs it keeps,
// with the texel's f and emission at the hit), its patch normal *n and its shading normal *ns.
static Bsdf eye_hit_bsdf(const EyeHit* h, uint pixel, const BundleIteration* it, __global const BundleElement* elements,
                         __global const uint* patch_element, __global const Material* materials,
                         __global const Material* patch_materials, uint uv_slots, __global const float4* eye_texels,
                         __global const float4* eye_normals, float3* n, float3* ns) {
  uint pe = patch_element[h->patch];
  *n = patch_normal(elements, pe);
  Bsdf bsdf = bsdf_from_material(rb_material(materials, patch_materials, uv_slots, elements[pe & ~BP_BACK_SIDE].material,
                                             h->patch));
  __global const float4* texel = eye_texels + BP_EYE_TEXELS * pixel;
  if (BP_FEATURE_TEXTURES && uv_slots > 0u && texel[1].w > 0.0f) {  // the texel's f and emission
    TexelMaterial t;
    t.base_color = make_float3(texel[0].x, texel[0].y, texel[0].z);
    t.metallic = texel[0].w;
    t.roughness = texel[1].x;
    t.emission = make_float3(texel[2].x, texel[2].y, texel[2].z);
    t.alpha = 1.0f;
    t.specular_textured = texel[1].y > 0.0f;
    t.dielectric_f0 = make_float3(texel[3].x, texel[3].y, texel[3].z);
    t.specular_weight = texel[3].w;
    bsdf_take_texel(&bsdf, &t);
  }
  *ns = *n;
  if (BP_FEATURE_SHADING_NORMALS && it->shading_normals) {
    float4 e = eye_normals[pixel];
    // as the path tracer's eye vertex has it (brdf.h): the patch normal is the hit's flat one
    *ns = bsdf_shading_normal(&bsdf, *n, make_float3(h->wo[0], h->wo[1], h->wo[2]), make_float3(e.x, e.y, e.z));
  }
  return bsdf;
}

// What the environment seen from the eye adds per iteration, weighted (returned) and raw (*raw): the
// empty prefix (RB's alone under product weights, PT's where light sampling gives it the eye's emission).
static float3 eye_environment(const EyeHit* h, const BundleIteration* it, __global const float* environment_texels,
                              float3* raw) {
  const EnvironmentMap map = environment_map(environment_texels, it->environment_width, it->environment_height);
  float3 env = environment_radiance(&map, make_float3(-h->wo[0], -h->wo[1], -h->wo[2]));
  *raw = env;
  float3 weighted = env;
  if (it->weight_mode == BP_WEIGHTS_PRODUCT && BP_FEATURE_LIGHT_SAMPLING && it->light_count > 0u)
    weighted = make_float3(0.0f, 0.0f, 0.0f);
  if (it->weight_mode == BP_WEIGHTS_PAPER) weighted = env * paper_rb_weight(0.0f, it->weight_ratio);
  return weighted;
}

// 6. Eye estimate of this iteration: the primary hit reflects its patch's incoming radiance towards
//    the eye, Le + 2 pi f(w_in -> w_view) cos(theta_in) L_in, weighted as the mode says, added to the
//    pixel's running sums (weighted, and raw when asked for).
__kernel void rb_eye(__global const EyeHit* hits, __global const BundleElement* elements,
                     __global const uint* patch_element, __global const Material* materials,
                     __global const float4* e_in, __global const uint* patch_vertices,
                     __global const float4* e_vertex, const uint gouraud, const BundleIteration it,
                     const uint pixels, __global float4* pixel_sum, __global const float4* eye_light,
                     __global const float4* eye_normals, __global const Material* patch_materials, const uint uv_slots,
                     __global const float4* eye_texels, __global const float* environment_texels,
                     const uint eye_blocks) {
  uint pixel = (uint)get_global_id(0);
  if (pixel >= pixels) return;
  EyeHit h = hits[pixel];
  if (h.patch == BP_NO_PATCH) {
    // The environment seen from the eye, weighted as an emitter the eye sees (in blocks: rb_eye_block).
    if (h.element != BP_NO_PATCH || eye_blocks) return;
    float3 env;
    float3 weighted = eye_environment(&h, &it, environment_texels, &env) * bp_private3(h.filter);
    env *= bp_private3(h.filter);
    if (env.x + env.y + env.z <= 0.0f) return;
    pixel_sum[pixel * it.eye_outputs] += (float4)(weighted.x, weighted.y, weighted.z, 0.0f);
    if (it.eye_outputs > 1) pixel_sum[pixel * it.eye_outputs + 1] += (float4)(env.x, env.y, env.z, 0.0f);
    return;
  }
  float3 n, ns;  // the patch normal (the weights' inputs) and the shading normal (the reflected radiance)
  Bsdf bsdf = eye_hit_bsdf(&h, pixel, &it, elements, patch_element, materials, patch_materials, uv_slots,
                           eye_texels, eye_normals, &n, &ns);
  if (eye_in_blocks(eye_blocks, &bsdf, n, ns)) return;  // gathered in blocks: rb_eye_block
  float3 wo = make_float3(h.wo[0], h.wo[1], h.wo[2]);
  float3 wi = facing(n, bp_private3(it.omega));
  BsdfValue v = bsdf_evaluate(&bsdf, n, wi, wo);  // about the patch normal: the weight inputs (docs/design.md §3)
  float3 transfer = eye_brdf(&bsdf, n, ns, wi, wo, v.f) * BP_TWO_PI;
  const uint slots = eye_slots(&it);
  float4 e0 = eye_irradiance(&h, &e_in[h.patch * it.chains], patch_vertices, e_vertex, gouraud, slots, 0u);
  float3 reflected0 = transfer * make_float3(e0.x, e0.y, e0.z);
  float3 weighted;
  if (it.weight_mode == BP_WEIGHTS_PRODUCT) {
    // chain 0 already carries prod beta of the earlier vertices; the eye vertex adds its own.
    // With light sampling the eye vertex's emission, like its direct light, is PT's alone.
    weighted = (BP_FEATURE_LIGHT_SAMPLING && it.light_count > 0u ? make_float3(0.0f, 0.0f, 0.0f) : bsdf.emission) +
               reflected0 * vertex_beta(bsdf.continuation, v.pdf_uv, it.weight_ratio, it.beta_heuristic);
    if (BP_FEATURE_LIGHT_SAMPLING && it.light_count > 0u && it.eye_direct_chain) {
      // --eye-direct shared: the eye vertex's direct light, weighted per fragment and per shadow ray
      // as RB's techniques of its last segment (no beta: that vertex is the segment's start).
      // The light samples' irradiance is interpolated like the chains; it is reflected along the hit
      // patch's own sample direction (exact for Lambert eye vertices, a patch-level stand-in otherwise).
      float4 ed = eye_irradiance(&h, &e_in[h.patch * it.chains + it.eye_direct_chain], patch_vertices, e_vertex,
                                 gouraud, slots, it.eye_direct_chain);
      float4 el = eye_irradiance(&h, &eye_light[2 * h.patch], patch_vertices, e_vertex, gouraud, slots, it.chains);
      float4 el_dir = eye_light[2 * h.patch + 1];
      weighted += transfer * make_float3(ed.x, ed.y, ed.z);
      if (el.x + el.y + el.z > 0.0f) {
        float3 el_wi = make_float3(el_dir.x, el_dir.y, el_dir.z);
        weighted += eye_brdf(&bsdf, n, ns, el_wi, wo, bsdf_evaluate(&bsdf, n, el_wi, wo).f) * make_float3(el.x, el.y, el.z);
      }
    }
  } else if (it.weight_mode == BP_WEIGHTS_PAPER) {
    float log_pstar = paper_log_pstar_step(bsdf.continuation, v.pdf_uv, e0.w);  // (10) at the eye vertex
    weighted = bsdf.emission * paper_rb_weight(0.0f, it.weight_ratio) +  // the emitter seen directly: P = 1
               reflected0 * paper_rb_weight(log_pstar, it.weight_ratio);
  } else {
    weighted = bsdf.emission + reflected0;
  }
  const float3 filter = bp_private3(h.filter);  // the panes in front of the eye vertex
  weighted *= filter;
  pixel_sum[pixel * it.eye_outputs] += (float4)(weighted.x, weighted.y, weighted.z, 0.0f);
  if (it.eye_outputs > 1) {
    float3 raw = bsdf.emission + reflected0;
    if (it.weight_mode == BP_WEIGHTS_PRODUCT) {
      float4 e1 = eye_irradiance(&h, &e_in[h.patch * it.chains + it.chains - 1u], patch_vertices, e_vertex, gouraud,
                                 slots, it.chains - 1u);
      raw = bsdf.emission + transfer * make_float3(e1.x, e1.y, e1.z);
    }
    raw *= filter;
    pixel_sum[pixel * it.eye_outputs + 1] += (float4)(raw.x, raw.y, raw.z, 0.0f);
  }
}

// 6b. The eye estimate in blocks (eye_in_blocks): per iteration, each Lambert patch adds to its
//     corners' block sums what rb_eye would reflect per unit f at a hit on that corner -- 2 pi beta
//     E_in (chain 0), with --eye-direct shared 2 pi E_in of the eye chain and the light sample where
//     it is in front, and 2 pi E_in of the raw chain -- with E_in the corner's Gouraud vertex (or the
//     patch's own, flat). Nothing where the patch faces omega edge-on (f is 0 there, as in rb_eye).
__kernel void rb_eye_patches(__global const BundleElement* elements, __global const uint* patch_element,
                             __global const Material* materials, __global const Material* patch_materials,
                             const uint uv_slots, __global const float4* e_in, __global const uint* patch_vertices,
                             __global const float4* e_vertex, const uint gouraud, const BundleIteration it,
                             const uint patches, __global const float4* eye_light, __global float4* eye_block) {
  uint p = (uint)get_global_id(0);
  if (p >= patches) return;
  uint pe = patch_element[p];
  float3 n = patch_normal(elements, pe);
  Bsdf bsdf = bsdf_from_material(rb_material(materials, patch_materials, uv_slots, elements[pe & ~BP_BACK_SIDE].material, p));
  if (!eye_in_blocks(1u, &bsdf, n, n)) return;
  float3 wi = facing(n, bp_private3(it.omega));
  float cos_in = dot(n, wi);
  const float reflects = cos_in > 0.0f ? BP_TWO_PI : 0.0f;  // 2 pi, or 0 where bsdf_evaluate gives f = 0
  float beta = 1.0f;
  if (it.weight_mode == BP_WEIGHTS_PRODUCT)
    beta = vertex_beta(bsdf.continuation, pdf_uv_cosine(cos_in), it.weight_ratio, it.beta_heuristic);
  const int eye_direct = BP_FEATURE_LIGHT_SAMPLING && it.light_count > 0u && it.eye_direct_chain;
  float light_in_front = 0.0f;
  if (eye_direct) {
    float4 el_dir = eye_light[2 * p + 1];
    light_in_front = dot(n, make_float3(el_dir.x, el_dir.y, el_dir.z)) > 0.0f ? 1.0f : 0.0f;
  }
  const uint raw_chain = it.weight_mode == BP_WEIGHTS_PRODUCT ? it.chains - 1u : 0u;
  const uint slots = eye_slots(&it), corners = gouraud ? 3u : 1u;
  for (uint j = 0; j < corners; ++j) {
    __global const float4* corner = gouraud ? &e_vertex[patch_vertices[3 * p + j] * slots] : &e_in[p * it.chains];
    float4 sum = corner[0] * (reflects * beta);
    if (eye_direct)
      sum += corner[it.eye_direct_chain] * reflects +
             (gouraud ? corner[it.chains] : eye_light[2 * p]) * light_in_front;
    eye_block[(3 * p + j) * it.eye_outputs] += sum;
    if (it.eye_outputs > 1) eye_block[(3 * p + j) * it.eye_outputs + 1] += corner[raw_chain] * reflects;
  }
}

// 6c. The block's eye estimates of the pixels gathered in blocks (eye_in_blocks), added to their sums:
//     iterations times the emission (weighted as rb_eye weighs it) plus f times the hit's
//     interpolation of its corners' block sums; the environment, iterations times its value.
__kernel void rb_eye_block(__global const EyeHit* hits, __global const BundleElement* elements,
                           __global const uint* patch_element, __global const Material* materials,
                           __global const uint* patch_vertices, const uint gouraud, const BundleIteration it,
                           const uint pixels, __global float4* pixel_sum, __global const float4* eye_normals,
                           __global const Material* patch_materials, const uint uv_slots,
                           __global const float4* eye_texels, __global const float* environment_texels,
                           __global const float4* eye_block, const float iterations) {
  uint pixel = (uint)get_global_id(0);
  if (pixel >= pixels) return;
  EyeHit h = hits[pixel];
  float3 weighted, raw;
  if (h.patch == BP_NO_PATCH) {
    if (h.element != BP_NO_PATCH) return;
    weighted = eye_environment(&h, &it, environment_texels, &raw) * iterations;
    raw *= iterations;
  } else {
    float3 n, ns;
    Bsdf bsdf = eye_hit_bsdf(&h, pixel, &it, elements, patch_element, materials, patch_materials, uv_slots,
                             eye_texels, eye_normals, &n, &ns);
    if (!eye_in_blocks(1u, &bsdf, n, ns)) return;  // rb_eye's, every iteration
    float3 wo = make_float3(h.wo[0], h.wo[1], h.wo[2]);
    float3 f = dot(n, wo) > 0.0f ? bsdf.kd * BP_INV_PI : make_float3(0.0f, 0.0f, 0.0f);
    __global const float4* b = &eye_block[3 * h.patch * it.eye_outputs];
    float4 block = b[0], block_raw = it.eye_outputs > 1 ? b[1] : (float4)(0.0f);
    if (gouraud) {
      float w0 = 1.0f - h.l1 - h.l2;
      block = b[0] * w0 + b[it.eye_outputs] * h.l1 + b[2 * it.eye_outputs] * h.l2;
      if (it.eye_outputs > 1) block_raw = b[1] * w0 + b[it.eye_outputs + 1] * h.l1 + b[2 * it.eye_outputs + 1] * h.l2;
    }
    // With light sampling the eye vertex's emission, like its direct light, is PT's alone.
    float3 emission_weighted =
        it.weight_mode == BP_WEIGHTS_PRODUCT && BP_FEATURE_LIGHT_SAMPLING && it.light_count > 0u
            ? make_float3(0.0f, 0.0f, 0.0f) : bsdf.emission;
    weighted = emission_weighted * iterations + f * make_float3(block.x, block.y, block.z);
    raw = bsdf.emission * iterations + f * make_float3(block_raw.x, block_raw.y, block_raw.z);
  }
  weighted *= bp_private3(h.filter);  // the panes in front of the eye vertex
  raw *= bp_private3(h.filter);
  pixel_sum[pixel * it.eye_outputs] += (float4)(weighted.x, weighted.y, weighted.z, 0.0f);
  if (it.eye_outputs > 1) pixel_sum[pixel * it.eye_outputs + 1] += (float4)(raw.x, raw.y, raw.z, 0.0f);
}
