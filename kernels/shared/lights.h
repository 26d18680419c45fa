// Light sampling (docs/design.md §3, "Light sampling as a strategy"): the scene's lights -- emissive
// triangles and KHR_lights_punctual point, spot and directional lights -- chosen for the receiving patch by the
// light tree (light_tree.h) or by power alone, and the density of the direction a light sample
// takes, in the uv measure (eq. 7) like every other density.
#ifndef BP_SHARED_LIGHTS_H
#define BP_SHARED_LIGHTS_H
#include "shared/compat.h"
#include "shared/types.h"
#include "shared/light_tree.h"
#include "shared/texture.h"
#include "shared/environment_map.h"

#define BP_LIGHT_TRIANGLE 0u
#define BP_LIGHT_POINT 1u
#define BP_LIGHT_SPOT 2u
#define BP_LIGHT_DIRECTIONAL 3u  // a sun: parallel light of irradiance `intensity` (W m^-2) along `axis`; after the others
#define BP_LIGHT_ENVIRONMENT 4u  // the environment map (environment_map.h); the very last when the scene has one
// Directional lights and the environment are "infinite": no position for the light tree to bound.
BP_FN int light_is_infinite(bp_u32 type) { return type >= BP_LIGHT_DIRECTIONAL; }

#define BP_LIGHT_SELECTION_TREE 0u   // by the light tree, for the receiving patch (--light-selection tree)
#define BP_LIGHT_SELECTION_POWER 1u  // by power alone, the same for every receiver

// One light. host/scene/lights.cpp builds the list and the selection cdf; shared_types_check.cpp
// checks the layout.
typedef struct {
  float position[3];     // triangle: vertex p0; point, spot: the light's position
  bp_u32 type;           // BP_LIGHT_*
  float edge1[3];        // triangle: p1 - p0
  bp_u32 material;       // triangle: its material (emission, sides)
  float edge2[3];        // triangle: p2 - p0
  float area;            // triangle: area, m^2
  float axis[3];         // triangle: unit front normal; spot: unit direction of the cone; directional: of travel
  float select_probability;  // by power
  float intensity[3];    // point, spot: radiant intensity I per colour, W sr^-1 (glTF: candela); directional: E, W m^-2 (lux)
  float cos_outer;       // spot: cos of the outer cone angle (no light beyond)
  float cos_inner;       // spot: cos of the inner cone angle (full intensity within)
  bp_u32 tree_trail[2];  // its leaf's path from the light tree's root: bit k set = second child at depth k
  bp_u32 tree_depth;     // the leaf's depth (0: the only light)
  bp_u32 triangle;       // triangle: its scene triangle (texcoords of an emissive texture)
  bp_u32 pad[3];
} Light;

// A light sample as seen from a shading point x.
typedef struct {
  float3 wi;             // unit direction from x towards the light
  float distance;        // from x to the sampled point (the shadow ray's length)
  float3 radiance_over_pdf;  // incident radiance over the solid-angle density of wi: the estimator's L/p
  float pdf_uv;          // density of wi in the uv measure (2 pi p_solid); unused for a delta light
  int is_delta;          // point, spot and directional lights: only light sampling reaches them
  bp_u32 light;          // the light chosen
  float select_probability;  // P(choosing it | the receiving patch)
} LightSample;

// Index of the light whose cdf interval holds u (cdf[i] = sum of select probabilities up to i).
BP_FN bp_u32 light_pick(BP_GLOBAL const float* cdf, bp_u32 count, float u) {
  bp_u32 lo = 0u, hi = count - 1u;
  while (lo < hi) {
    bp_u32 mid = (lo + hi) / 2u;
    if (u < cdf[mid]) hi = mid; else lo = mid + 1u;
  }
  return lo;
}

// Density in the uv measure of reaching a point of an emissive triangle from distance d when its
// surface is crossed at cosine cos_light: p_uv = 2 pi p_area d^2 / cos_light (area to solid angle,
// then eq. 7). p_area = select probability / area, one number per emissive material
// (Material.light_pdf_area). Capped so the weights of docs/design.md §3 stay finite at grazing angles.
BP_FN float light_pdf_uv_area(float light_pdf_area, float distance, float cos_light) {
  if (light_pdf_area <= 0.0f || cos_light <= 0.0f) return 0.0f;
  return fmin(BP_TWO_PI * light_pdf_area * distance * distance / cos_light, 1e30f);
}

// Density in the uv measure of the environment light reaching direction wi when it is selected with
// probability select_probability: p_uv = 2 pi P(select) p_solid(wi) (eq. 7), capped as for areas.
BP_FN float environment_light_pdf_uv(float select_probability, const EnvironmentMap* m, float3 wi) {
  return fmin(BP_TWO_PI * select_probability * environment_pdf_solid_angle(m, wi), 1e30f);
}

// glTF spot cone (KHR_lights_punctual): smooth in cos between the outer and inner angles, squared.
BP_FN float spot_attenuation(float cos_axis, float cos_outer, float cos_inner) {
  float t = clamp((cos_axis - cos_outer) / fmax(cos_inner - cos_outer, 1e-3f), 0.0f, 1.0f);
  return t * t;
}

// Everything light selection reads: the lights, the power cdf, the light tree and the receiving
// patches; PT and RB see the same buffers, so they evaluate the same probabilities.
typedef struct {
  BP_GLOBAL const Light* lights;
  BP_GLOBAL const float* cdf;
  BP_GLOBAL const LightTreeNode* tree;
  BP_GLOBAL const LightReceiver* receivers;  // per patch
  bp_u32 count;
  bp_u32 selection;  // BP_LIGHT_SELECTION_*
  TextureSet textures;  // emissive textures (uv_slots 0: none; light_set leaves it so)
  EnvironmentMap environment;  // the environment light's map (width 0: none; light_set leaves it so)
} LightSet;

BP_FN LightSet light_set(BP_GLOBAL const Light* lights, BP_GLOBAL const float* cdf, BP_GLOBAL const LightTreeNode* tree,
                         BP_GLOBAL const LightReceiver* receivers, bp_u32 count, bp_u32 selection) {
  LightSet s;
  s.lights = lights;
  s.cdf = cdf;
  s.tree = tree;
  s.receivers = receivers;
  s.count = count;
  s.selection = selection;
  s.textures.views = 0;
  s.textures.texels = 0;
  s.textures.materials = 0;
  s.textures.texcoords = 0;
  s.textures.uv_slots = 0u;
  s.environment = environment_map(0, 0u, 0u);
  return s;
}

// A light chosen for a receiver, and the probability it was chosen with.
typedef struct {
  bp_u32 light;
  float probability;
} LightPick;

// The lights of a tree leaf (one panel's triangles) are chosen by power among themselves: the share
// of `light`, or, with light = BP_NO_LIGHT, the light that u picks and its share.
BP_FN LightPick light_leaf_pick(const LightSet* set, BP_GLOBAL const LightTreeNode* leaf, float u, bp_u32 light) {
  const bp_u32 first = leaf->child, count = leaf->leaf_lights;
  LightPick pick;
  pick.light = first;
  pick.probability = 1.0f;
  if (count <= 1u) return pick;
  float total = 0.0f;
  for (bp_u32 i = 0u; i < count; ++i) total += set->lights[first + i].select_probability;
  if (!(total > 0.0f)) {  // dark lights only: uniform
    pick.light = light != BP_NO_LIGHT ? light : first + (bp_u32)fmin(u * (float)count, (float)(count - 1u));
    pick.probability = 1.0f / (float)count;
    return pick;
  }
  if (light == BP_NO_LIGHT) {
    float target = u * total, running = 0.0f;
    pick.light = first + count - 1u;
    for (bp_u32 i = 0u; i < count; ++i) {
      running += set->lights[first + i].select_probability;
      if (target < running) {
        pick.light = first + i;
        break;
      }
    }
  } else {
    pick.light = light;
  }
  pick.probability = set->lights[pick.light].select_probability / total;
  return pick;
}

// Directional lights and the environment have no position for the tree to bound: they are the
// lights after the tree's, chosen among themselves by their share of the power (select_probability).
// Their total share of the power, and the index of the first of them (count: none).
BP_FN float light_directional_share(const LightSet* set, bp_u32* first) {
  float share = 0.0f;
  bp_u32 i = set->count;
  while (i > 0u && light_is_infinite(set->lights[i - 1u].type)) share += set->lights[--i].select_probability;
  *first = i;
  return share;
}

// Their share of the choice for one receiving patch: the power share S, its odds against the tree's
// lights scaled by how much of them reaches the patch (LightReceiver.infinite_visibility, v):
//   S_r = S v / (S v + 1 - S);  all of it where they are all the lights. A patch that the sun cannot
// see rarely spends its sample on it; v > 0 keeps every light possible, so the estimate unbiased.
BP_FN float light_infinite_share(const LightSet* set, bp_u32 receiver_patch, float share, bp_u32 first_infinite) {
  if (first_infinite == 0u) return 1.0f;
  if (!(share > 0.0f)) return 0.0f;
  const float odds = share * set->receivers[receiver_patch].infinite_visibility;
  return odds / (odds + (1.0f - share));
}

// A light for the receiving patch, and its selection probability.
BP_FN LightPick light_select(const LightSet* set, bp_u32 receiver_patch, float u) {
  if (set->selection == BP_LIGHT_SELECTION_TREE) {
    bp_u32 first_directional;
    const float power_share = light_directional_share(set, &first_directional);
    const float directional = light_infinite_share(set, receiver_patch, power_share, first_directional);
    if (first_directional < set->count && u < directional) {
      // by power among the directional lights and the environment, u rescaled into their power
      float target = u / directional * power_share, running = 0.0f;
      LightPick pick;
      pick.light = set->count - 1u;
      for (bp_u32 i = first_directional; i < set->count; ++i) {
        running += set->lights[i].select_probability;
        if (target < running) {
          pick.light = i;
          break;
        }
      }
      pick.probability = set->lights[pick.light].select_probability / power_share * directional;
      return pick;
    }
    const float tree_share = 1.0f - directional;
    if (directional > 0.0f) u = fmin(fmax((u - directional) / tree_share, 0.0f), 0.99999994f);
    LightTreeLeaf leaf = light_tree_select(set->tree, &set->receivers[receiver_patch], u);
    LightPick pick = light_leaf_pick(set, &set->tree[leaf.node], leaf.u, BP_NO_LIGHT);
    pick.probability *= leaf.probability;
    if (directional > 0.0f) pick.probability *= tree_share;
    return pick;
  }
  LightPick pick;
  pick.light = light_pick(set->cdf, set->count, u);
  pick.probability = set->lights[pick.light].select_probability;
  return pick;
}

// P(light_select picks `light` | the receiving patch): the same number the pick carried.
BP_FN float light_select_probability(const LightSet* set, bp_u32 receiver_patch, bp_u32 light) {
  BP_GLOBAL const Light* l = &set->lights[light];
  if (set->selection != BP_LIGHT_SELECTION_TREE) return l->select_probability;
  bp_u32 first_directional;
  const float power_share = light_directional_share(set, &first_directional);
  const float directional = light_infinite_share(set, receiver_patch, power_share, first_directional);
  if (light_is_infinite(l->type)) return l->select_probability / power_share * directional;
  bp_u32 leaf = 0u;
  float p = light_tree_probability(set->tree, &set->receivers[receiver_patch], l->tree_trail[0], l->tree_trail[1],
                                   l->tree_depth, &leaf);
  p = light_leaf_pick(set, &set->tree[leaf], 0.0f, light).probability * p;
  return directional > 0.0f ? p * (1.0f - directional) : p;
}

// Light sampling's area density on the emitter that patch emitter_patch is part of, as seen from
// the receiving patch (for the weights of an emitter reached otherwise: PT's BSDF sample, RB's
// bundle): P(select) / area. By power: the material's, as before the tree.
BP_FN float light_pdf_area_from(const LightSet* set, BP_GLOBAL const Material* materials, bp_u32 receiver_patch,
                                bp_u32 emitter_patch, bp_u32 emitter_material) {
  if (set->selection != BP_LIGHT_SELECTION_TREE) return materials[emitter_material].light_pdf_area;
  bp_u32 light = set->receivers[emitter_patch].light;
  if (light == BP_NO_LIGHT || !(set->lights[light].area > 0.0f)) return 0.0f;
  return light_select_probability(set, receiver_patch, light) / set->lights[light].area;
}

// Samples a point (u1, u2) of the light `pick` chose, as seen from x.
BP_FN LightSample light_sample_picked(const LightSet* set, BP_GLOBAL const Material* materials, LightPick pick,
                                      float3 x, float u1, float u2) {
  LightSample s;
  BP_GLOBAL const Light* l = &set->lights[pick.light];
  s.light = pick.light;
  s.select_probability = pick.probability;
  float3 target = bp_load3(l->position);
  float root = sqrt(u1);
  if (l->type == BP_LIGHT_TRIANGLE) {  // uniform on the triangle: barycentrics (1 - sqrt u1, sqrt u1 (1 - u2), sqrt u1 u2)
    target += bp_load3(l->edge1) * (root * (1.0f - u2)) + bp_load3(l->edge2) * (root * u2);
  }
  float3 to_light = target - x;
  s.distance = length(to_light);
  s.wi = to_light / s.distance;
  if (l->type == BP_LIGHT_DIRECTIONAL) {  // towards the sun, as far as any ray goes
    s.wi = -bp_load3(l->axis);
    s.distance = BP_FLOAT_MAX;
  }
  if (l->type == BP_LIGHT_ENVIRONMENT) {  // by the map's luminance, as far as any ray goes
    s.wi = environment_sample(&set->environment, u1, u2).wi;
    s.distance = BP_FLOAT_MAX;
  }
  s.is_delta = l->type != BP_LIGHT_TRIANGLE && l->type != BP_LIGHT_ENVIRONMENT;
  s.radiance_over_pdf = make_float3(0.0f, 0.0f, 0.0f);
  s.pdf_uv = 0.0f;
  if (!(s.distance > 0.0f) || !(pick.probability > 0.0f)) return s;
  if (l->type == BP_LIGHT_TRIANGLE) {
    BP_GLOBAL const Material* m = &materials[l->material];
    float cos_light = -dot(bp_load3(l->axis), s.wi);  // > 0: x sees the front
    if (m->flags & BP_MATERIAL_DOUBLE_SIDED) cos_light = fabs(cos_light);
    float pdf_area = set->selection == BP_LIGHT_SELECTION_TREE ? pick.probability / l->area : m->light_pdf_area;
    s.pdf_uv = light_pdf_uv_area(pdf_area, s.distance, cos_light);
    float3 le = bp_load3(m->emission);
    if (BP_FEATURE_TEXTURES && set->textures.uv_slots > 0u) {  // an emissive texture's texel at the sampled point
      le = texel_emission(&set->textures, l->material, l->triangle, root * (1.0f - u2), root * u2, le);
      // where an alpha mask cuts the emitter away nothing emits (PT's rays pass there too)
      if (!alpha_is_surface(&set->textures, l->material, l->triangle, root * (1.0f - u2), root * u2))
        le = make_float3(0.0f, 0.0f, 0.0f);
    }
    if (s.pdf_uv > 0.0f) s.radiance_over_pdf = le * (BP_TWO_PI / s.pdf_uv);  // L / p_solid
  } else if (l->type == BP_LIGHT_ENVIRONMENT) {
    // the density and radiance as functions of the direction, as every other technique evaluates them
    s.pdf_uv = environment_light_pdf_uv(pick.probability, &set->environment, s.wi);
    if (s.pdf_uv > 0.0f) s.radiance_over_pdf = environment_radiance(&set->environment, s.wi) * (BP_TWO_PI / s.pdf_uv);
  } else if (l->type == BP_LIGHT_DIRECTIONAL) {
    s.radiance_over_pdf = bp_load3(l->intensity) * (1.0f / pick.probability);  // E / P(select): L / p_solid of a delta
  } else {
    // E = I / d^2 from the light's direction: L / p_solid is I / (d^2 P(select)).
    float falloff = 1.0f;
    if (l->type == BP_LIGHT_SPOT) falloff = spot_attenuation(dot(bp_load3(l->axis), -s.wi), l->cos_outer, l->cos_inner);
    s.radiance_over_pdf = bp_load3(l->intensity) * (falloff / (s.distance * s.distance * pick.probability));
  }
  return s;
}

// Samples a light for the receiving patch (u_pick) and a point on it (u1, u2) as seen from x, a
// point of that patch.
BP_FN LightSample light_sample(const LightSet* set, BP_GLOBAL const Material* materials, bp_u32 receiver_patch,
                               float3 x, float u_pick, float u1, float u2) {
  return light_sample_picked(set, materials, light_select(set, receiver_patch, u_pick), x, u1, u2);
}

// p_L of a ray from the receiving patch that leaves the scene along wi: the environment light's
// (light = its index, BP_NO_LIGHT where light sampling does not take it) -- for PT's BSDF samples
// and RB's bundles, the same number light_sample gave the light techniques.
BP_FN float light_pdf_uv_environment(const LightSet* set, bp_u32 receiver_patch, bp_u32 light, float3 wi) {
  if (light == BP_NO_LIGHT || set->environment.width == 0u) return 0.0f;
  return environment_light_pdf_uv(light_select_probability(set, receiver_patch, light), &set->environment, wi);
}

#endif  // BP_SHARED_LIGHTS_H
