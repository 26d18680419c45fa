// Path tracer megakernel (docs/design.md §5): one work-item per pixel, samples_per_launch samples each.
// The loop calls stage functions: camera ray, intersect, surface, emission weight, sample, step.
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/camera.h"
#include "shared/bvh.h"
#include "shared/surface.h"
#include "shared/brdf.h"
#include "shared/path_pdf.h"
#include "shared/weights.h"
#include "shared/lights.h"
#include "shared/textured.h"
#include "shared/alpha_mask.h"
#include "shared/through_panes.h"
#include "shared/dielectric.h"

typedef struct {
  BP_GLOBAL const BvhNode* nodes;
  BP_GLOBAL const BvhTriangle* triangles;
  BP_GLOBAL const TriangleShading* shading;
  BP_GLOBAL const ClusterFan* cluster_fans;
  BP_GLOBAL const Material* materials;
  BP_GLOBAL const float* shading_normals;  // NORMAL corners, 9 floats per triangle (params.shading_normals)
  BP_GLOBAL const float* tangents;         // TANGENT corners of normal-mapped triangles, 12 floats each (normal_map.h)
  LightSet lights;  // with the per-patch receivers that light selection reads, and the textures
  BP_GLOBAL const Material* patch_materials;  // textures: per patch, its mean material (host/scene/textures.h)
  bp_u32 alpha_masks;  // 1: some material has alphaMode MASK (alpha_mask.h)
} SceneRefs;

// The BSDF at a hit: its material's, or with textures its patch's mean with the texel's f and
// emission (textured.h: every weight input stays patch-level, as RB has it).
static Bsdf pt_bsdf(const SceneRefs* scene, const SurfaceHit* surface, const Hit* hit) {
  if (!BP_FEATURE_TEXTURES || scene->lights.textures.uv_slots == 0u)
    return bsdf_from_material(&scene->materials[surface->material]);
  Bsdf bsdf = bsdf_from_material(&scene->patch_materials[surface->patch]);
  bsdf_apply_texel(&bsdf, &scene->lights.textures, surface->material, hit->triangle, hit->b1, hit->b2);
  return bsdf;
}

typedef struct {
  float3 weighted;  // each emission times w_PT of its prefix
  float3 raw;       // unweighted
} PathRadiance;

// The product of beta of the vertices before the one at `depth` (0: the eye vertex): the prefix of
// the last-segment split of docs/design.md §3. 0 where PT owns the last segment alone: direct light at
// the eye vertex under --eye-direct pt, and every path when PT runs without RB.
static float last_segment_prefix_beta(const PathTraceParams* params, const PathPdf* pdf, bp_u32 depth) {
  if (params->weight_mode != BP_WEIGHTS_PRODUCT || (depth == 0u && !params->eye_direct_shared)) return 0.0f;
  return pdf->beta_product;
}

// The four-technique weights of a last segment from the vertex at `depth` (docs/design.md §3): at the eye
// vertex under --eye-direct shared, RB's share from the view-independent proxy density; elsewhere
// the prefix product and PT's density about the patch normal on both sides (pdf_bsdf_patch, what RB
// computes), PT's own share split by its true density (pdf_bsdf, about the shading normal). The raw
// layer's PT-alone weights are the same with no RB share (prefix 0).
static LastSegmentWeights pt_last_segment_weights(const PathTraceParams* params, bp_u32 depth, float prefix_beta,
                                                  float pdf_bsdf_patch, float pdf_bsdf, float pdf_proxy,
                                                  float pdf_light, int is_delta) {
  if (depth == 0u && prefix_beta > 0.0f)
    return eye_segment_weights(params->weight_ratio, params->rb_light_rate, pdf_proxy, pdf_bsdf, pdf_light, is_delta);
  return last_segment_split(prefix_beta, params->weight_ratio, params->rb_light_rate, pdf_bsdf_patch, pdf_bsdf,
                            pdf_light, is_delta);
}

// PT's density (uv) of wi given wo about the flat patch normal: the weight input RB can compute
// (docs/design.md §3); the same as the sampling density where the shading normal is the flat one.
static float pdf_uv_patch(const SurfaceHit* surface, const Bsdf* bsdf, float3 wi, float3 wo, float pdf_uv_shading) {
  if (!BP_FEATURE_SHADING_NORMALS) return pdf_uv_shading;
  float3 d = surface->shading_normal - surface->normal;
  return d.x == 0.0f && d.y == 0.0f && d.z == 0.0f ? pdf_uv_shading : bsdf_pdf_uv(bsdf, surface->normal, wi, wo);
}

// Next-event estimation at a vertex: one light sample, one shadow ray, weighted as the PT light
// technique of docs/design.md §3 (the PT-alone balance heuristic for the raw layer).
static void add_light_sample(const SceneRefs* scene, const PathTraceParams* params, const SurfaceHit* surface,
                             const Bsdf* bsdf, float3 wo, float3 throughput, bp_u32 depth, float prefix_beta,
                             Rng* rng, PathRadiance* radiance, bp_u32* rays) {
  float u_pick = rng_uniform(rng), u1 = rng_uniform(rng), u2 = rng_uniform(rng);
  float3 x = surface->position + surface->normal * params->ray_epsilon;
  LightSample ls = light_sample(&scene->lights, scene->materials, surface->patch, x, u_pick, u1, u2);
  float cos_x = dot(surface->normal, ls.wi);  // geometric: the light must be in front of the surface itself
  float cos_shading = dot(surface->shading_normal, ls.wi);
  if (!(cos_x > 0.0f) || !(cos_shading > 0.0f) ||
      ls.radiance_over_pdf.x + ls.radiance_over_pdf.y + ls.radiance_over_pdf.z <= 0.0f)
    return;
  // An area light's own surface is at ls.distance: stop the shadow ray a few offsets short of it.
  float t_max = ls.is_delta ? ls.distance : ls.distance - 4.0f * params->ray_epsilon;
  *rays += 1u;
  if (t_max <= 0.0f) return;
  // through thin panes, attenuated (docs/design.md §11): the same weights as without them
  float3 through = shadow_transmittance(scene->nodes, scene->triangles, scene->shading, scene->materials,
                                        &scene->lights.textures, scene->alpha_masks, x, ls.wi, t_max,
                                        params->ray_epsilon);
  if (through.x + through.y + through.z <= 0.0f) return;
  BsdfValue v = bsdf_evaluate(bsdf, surface->shading_normal, ls.wi, wo);
  float pdf_bsdf = bsdf->continuation * v.pdf_uv;  // s p_b
  float pdf_bsdf_patch = bsdf->continuation * pdf_uv_patch(surface, bsdf, ls.wi, wo, v.pdf_uv);
  // f cos L / p_solid  (the light-sampling estimator of the rendering equation's integral)
  float3 contribution = throughput * through * v.f * ls.radiance_over_pdf * cos_shading;
  LastSegmentWeights w = pt_last_segment_weights(params, depth, prefix_beta, pdf_bsdf_patch, pdf_bsdf,
                                                 depth == 0u ? eye_direct_material_proxy_pdf_uv(
                                                                   &scene->materials[surface->material], cos_x)
                                                             : 0.0f,  // read at the eye vertex alone
                                                 ls.pdf_uv, ls.is_delta);
  // --rb-sun own: RB's patches also take samples of the sun of their own, at every vertex but the
  // eye's (whose share, under --eye-direct shared, RB takes from its chosen sample alone)
  if (depth > 0u && params->rb_sun_own_samples > 0u && scene->lights.lights[ls.light].type == BP_LIGHT_DIRECTIONAL)
    w = delta_light_weights(prefix_beta, params->weight_ratio, params->rb_light_rate, ls.select_probability,
                            (float)params->rb_sun_own_samples);
  // The raw layer's PT-alone weights: the same as w without a prefix (pt mode, the eye vertex).
  LastSegmentWeights alone =
      prefix_beta > 0.0f ? last_segment_split(0.0f, params->weight_ratio, params->rb_light_rate, pdf_bsdf_patch,
                                              pdf_bsdf, ls.pdf_uv, ls.is_delta)
                         : w;
  radiance->weighted += contribution * w.pt_light;
  radiance->raw += contribution * alone.pt_light;
}

// A ray that leaves the scene along dir sees the environment (--environment), weighted as an emitter:
// seen from the eye, by the empty prefix as the eye's emission (PT's alone with light sampling, RB's
// alone under product weights without it, rb_eye); after a bounce, as the PT BSDF technique of the
// last segment with the environment light's p_L of dir from the patch that sampled it (its RB bundle
// technique is the radiance a patch receives where nothing is in front, rb_tile_resolve).
static void add_environment(const SceneRefs* scene, const PathTraceParams* params, const PathPdf* pdf, bp_u32 depth,
                            float3 dir, float3 throughput, int light_sampling, float last_prefix_beta,
                            float last_pdf_bsdf_patch, float last_pdf_bsdf, float last_pdf_proxy, bp_u32 last_patch,
                            int last_delta, PathRadiance* radiance) {
  float3 seen = throughput * environment_radiance(&scene->lights.environment, dir);
  if (seen.x + seen.y + seen.z <= 0.0f) return;
  if (!light_sampling) {
    radiance->raw += seen;
    radiance->weighted += seen * pt_emission_weight(pdf, params->weight_mode, params->weight_ratio);
  } else if (depth == 0u) {
    radiance->raw += seen;
    radiance->weighted += seen;
  } else {
    float pdf_light =
        last_delta ? 0.0f : light_pdf_uv_environment(&scene->lights, last_patch, params->environment_light, dir);
    LastSegmentWeights w = pt_last_segment_weights(params, depth - 1u, last_prefix_beta, last_pdf_bsdf_patch,
                                                   last_pdf_bsdf, last_pdf_proxy, pdf_light, 0);
    LastSegmentWeights alone =
        last_prefix_beta > 0.0f ? last_segment_split(0.0f, params->weight_ratio, params->rb_light_rate,
                                                     last_pdf_bsdf_patch, last_pdf_bsdf, pdf_light, 0)
                                : w;
    radiance->weighted += seen * w.pt_bsdf;
    radiance->raw += seen * alone.pt_bsdf;
  }
}

#define BP_DELTA_RUN_BEFORE_ROULETTE 64u
#define BP_DELTA_ROULETTE_SURVIVAL 0.9f

// Radiance of one path (one pixel sample). Counts the rays it traces.
static PathRadiance trace_path(const SceneRefs* scene, const PathTraceParams* params, float3 origin, float3 dir,
                               Rng* rng, bp_u32* rays) {
  PathRadiance radiance;
  radiance.weighted = make_float3(0.0f, 0.0f, 0.0f);
  radiance.raw = make_float3(0.0f, 0.0f, 0.0f);
  float3 throughput = make_float3(1.0f, 1.0f, 1.0f);
  PathPdf pdf = path_pdf_start();
  const int light_sampling = BP_FEATURE_LIGHT_SAMPLING && params->light_count > 0u;
  // Of the vertex that sampled dir: its prefix, s p_b (sampled, and about the patch normal), and the
  // eye vertex's proxy density of dir.
  float last_prefix_beta = 0.0f, last_pdf_bsdf = 0.0f, last_pdf_bsdf_patch = 0.0f, last_pdf_proxy = 0.0f;
  bp_u32 last_patch = 0u;  // and its patch
  int last_delta = 0;      // 1: dir was sampled by a delta vertex (a mirror, a refraction): p_L 0
  float3 medium = make_float3(0.0f, 0.0f, 0.0f);  // attenuation (m^-1) of the refractor the ray is inside
  float3 vertex = origin;  // where the segment starts, before the offset of origin
  bp_u32 delta_run = 0u;   // delta vertices in a row just before this one
  for (bp_u32 depth = 0; depth < params->max_depth; ++depth) {
    Hit hit;
    *rays += 1u;
    bp_u32 pane_event;  // through thin panes: passed (throughput times their transmittance), or stopped at one
    if (!closest_hit_through_panes(scene->nodes, scene->triangles, scene->shading, scene->materials,
                                   &scene->lights.textures, scene->alpha_masks, origin, dir, params->ray_epsilon, 1,
                                   rng, &throughput, &pane_event, &hit, rays)) {
      if (BP_FEATURE_TRANSMISSION) throughput *= medium_transmittance(medium, BP_FLOAT_MAX);
      add_environment(scene, params, &pdf, depth, dir, throughput, light_sampling, last_prefix_beta,
                      last_pdf_bsdf_patch, last_pdf_bsdf, last_pdf_proxy, last_patch, last_delta, &radiance);
      break;
    }
    SurfaceHit surface = surface_at_shaded(scene->shading, scene->cluster_fans, scene->shading_normals, params->shading_normals,
                                           &scene->lights.textures, scene->tangents, hit.triangle, hit.b1, hit.b2,
                                           origin + dir * hit.t, dir);
    if (BP_FEATURE_TRANSMISSION) throughput *= medium_transmittance(medium, length(surface.position - vertex));
    vertex = surface.position;  // Beer-Lambert over the segment between the two surfaces, not from the offset
    int delta = BP_FEATURE_TRANSMISSION && pane_event == BP_PANE_MIRROR;
    if (delta) dir = reflect_about(-dir, surface.normal);  // throughput already times F T / P(mirror)
    BP_GLOBAL const Material* hit_material = &scene->materials[surface.material];
    if (BP_FEATURE_TRANSMISSION && !delta && (hit_material->flags & BP_MATERIAL_REFRACTOR)) {
      const int front = surface.reflects;
      const float rest = front || (hit_material->flags & BP_MATERIAL_DOUBLE_SIDED)
                             ? bsdf_from_material(hit_material).continuation : 0.0f;
      DielectricSample ds =
          dielectric_sample(-dir, surface.shading_normal, surface.normal, front, hit_material->ior,
                            hit_material->transmission, bp_load3(hit_material->transmission_tint), rest,
                            rng_uniform(rng));
      if (ds.event == BP_DIELECTRIC_ABSORBED) break;
      throughput *= ds.factor;
      if (ds.event == BP_DIELECTRIC_REFRACT)  // into the medium through the front, out through the back
        medium = front ? bp_load3(hit_material->attenuation) : make_float3(0.0f, 0.0f, 0.0f);
      delta = ds.event != BP_DIELECTRIC_REST;
      if (delta) dir = ds.wi;
    }
    if (delta) {
      // A delta vertex (docs/design.md §11): a pane's mirror, or a refractor's refraction or reflection;
      // PT's alone. beta 0 (w_RB = 0 from here on), no light sample, and the vertex after it sees
      // emitters by this direction alone: p_L 0 and any positive s p_b in the last-segment split.
      // Past BP_DELTA_RUN_BEFORE_ROULETTE delta vertices in a row (a ray trapped by total internal
      // reflection, as in a glass cube lit from inside), Russian roulette: unbiased, and no path
      // runs to --max-depth.
      if (++delta_run > BP_DELTA_RUN_BEFORE_ROULETTE) {
        if (rng_uniform(rng) >= BP_DELTA_ROULETTE_SURVIVAL) break;
        throughput *= 1.0f / BP_DELTA_ROULETTE_SURVIVAL;
      }
      if (params->weight_mode == BP_WEIGHTS_PAPER) path_pdf_step(&pdf, 1.0f, BP_FLOAT_MAX);  // P* infinite: w_PT 1
      if (params->weight_mode == BP_WEIGHTS_PRODUCT) path_pdf_multiply_beta(&pdf, 0.0f);
      last_prefix_beta = 0.0f;
      last_pdf_bsdf = last_pdf_bsdf_patch = 1.0f;
      last_delta = 1;
      last_patch = surface.patch;
      origin = surface.position + surface.normal * (dot(surface.normal, dir) > 0.0f ? params->ray_epsilon
                                                                                     : -params->ray_epsilon);
      continue;
    }
    if (!surface.reflects && !(hit_material->flags & BP_MATERIAL_DOUBLE_SIDED)) break;
    delta_run = 0u;
    Bsdf bsdf = pt_bsdf(scene, &surface, &hit);
    float3 wo = -dir;
    if (BP_FEATURE_SHADING_NORMALS)  // the normal a glossy lobe can use from wo (brdf.h)
      surface.shading_normal = bsdf_shading_normal(&bsdf, surface.normal, wo, surface.shading_normal);

    // Emission picked up after this prefix, weighted with w_PT of the prefix (docs/design.md §3); with
    // light sampling, as the PT BSDF technique of the last segment unless the eye sees it.
    float3 emitted = throughput * bsdf.emission;
    const int emits = emitted.x + emitted.y + emitted.z > 0.0f;
    if (emits && !light_sampling) {
      radiance.raw += emitted;
      radiance.weighted += emitted * pt_emission_weight(&pdf, params->weight_mode, params->weight_ratio);
    } else if (emits && depth == 0u) {  // the emitter seen directly: PT's alone with light sampling, as its direct light
      radiance.raw += emitted;
      radiance.weighted += emitted;
    } else if (emits) {
      float pdf_light = last_delta ? 0.0f
                                   : light_pdf_uv_area(light_pdf_area_from(&scene->lights, scene->materials, last_patch,
                                                                           surface.patch, surface.material),
                                                       hit.t, dot(surface.normal, wo));
      LastSegmentWeights w = pt_last_segment_weights(params, depth - 1u, last_prefix_beta, last_pdf_bsdf_patch,
                                                     last_pdf_bsdf, last_pdf_proxy, pdf_light, 0);
      LastSegmentWeights alone =
          last_prefix_beta > 0.0f ? last_segment_split(0.0f, params->weight_ratio, params->rb_light_rate,
                                                       last_pdf_bsdf_patch, last_pdf_bsdf, pdf_light, 0)
                                  : w;
      radiance.weighted += emitted * w.pt_bsdf;
      radiance.raw += emitted * alone.pt_bsdf;
    }

    float prefix_beta = last_segment_prefix_beta(params, &pdf, depth);
    if (light_sampling && bsdf.continuation > 0.0f)  // a black surface reflects no light sample
      add_light_sample(scene, params, &surface, &bsdf, wo, throughput, depth, prefix_beta, rng, &radiance, rays);

    // Russian roulette on the material-only continuation probability s.
    if (rng_uniform(rng) >= bsdf.continuation) break;
    float u_lobe = rng_uniform(rng), u1 = rng_uniform(rng), u2 = rng_uniform(rng);
    BsdfSample sample = bsdf_sample(&bsdf, surface.shading_normal, wo, u_lobe, u1, u2);
    if (sample.pdf_uv <= 0.0f) break;
    float cos_geometric = dot(surface.normal, sample.wi);
    if (!(cos_geometric > 0.0f)) break;  // below the surface itself: the shading normal's trap (docs/design.md §6)
    float cos_theta = dot(surface.shading_normal, sample.wi);
    // f cos / (s p_solid_angle), with p_solid_angle = pdf_uv / 2 pi  (7)
    throughput *= sample.f *
                  (cos_theta * BP_TWO_PI / (bsdf.continuation * sample.pdf_uv));
    // Every weight input is patch-level (docs/design.md §3): the density about the flat normal, as RB has it.
    const float pdf_patch = pdf_uv_patch(&surface, &bsdf, sample.wi, wo, sample.pdf_uv);
    last_prefix_beta = prefix_beta;
    last_pdf_bsdf = bsdf.continuation * sample.pdf_uv;
    last_pdf_bsdf_patch = bsdf.continuation * pdf_patch;
    if (depth == 0u) last_pdf_proxy = eye_direct_material_proxy_pdf_uv(&scene->materials[surface.material], cos_geometric);
    last_patch = surface.patch;
    last_delta = 0;
    // Only the weights of the mode need the pdf state: q and r for paper, prod beta for product.
    if (params->weight_mode == BP_WEIGHTS_PAPER) path_pdf_step(&pdf, bsdf.continuation, pdf_patch);
    if (params->weight_mode == BP_WEIGHTS_PRODUCT)
      path_pdf_multiply_beta(
          &pdf, vertex_beta(bsdf.continuation, pdf_patch, params->weight_ratio, params->beta_heuristic));
    origin = surface.position + surface.normal * params->ray_epsilon;
    dir = sample.wi;
  }
  return radiance;
}

__kernel void pathtrace(__global const BvhNode* nodes, __global const BvhTriangle* triangles,
                        __global const TriangleShading* shading, __global const Material* materials,
                        __global const Light* lights, __global const float* light_cdf,
                        const CameraParams camera, const PathTraceParams params,
                        __global PixelAccum* accum, __global const LightTreeNode* light_tree,
                        __global const LightReceiver* light_receivers, const uint light_selection,
                        __global const float* shading_normals, __global const TextureView* texture_views,
                        __global const uint* texels, __global const MaterialTextures* material_textures,
                        __global const float* texcoords, __global const Material* patch_materials,
                        const uint alpha_masks, __global const float* environment, __global const float* tangents,
                        __global const ClusterFan* cluster_fans) {
  bp_u32 pixel = (bp_u32)get_global_id(0);
  if (pixel >= camera.width * camera.height) return;
  SceneRefs scene = {nodes, triangles, shading, cluster_fans, materials, shading_normals, tangents,
                     light_set(lights, light_cdf, light_tree, light_receivers, params.light_count, light_selection),
                     patch_materials, alpha_masks};
  const TextureSet textures = {texture_views, texels, material_textures, texcoords, params.uv_slots};
  scene.lights.textures = textures;
  scene.lights.environment = environment_map(environment, params.environment_width, params.environment_height);
  bp_u32 px = pixel % camera.width, py = pixel / camera.width;
  float3 origin = make_float3(camera.position[0], camera.position[1], camera.position[2]);
  float3 sum = make_float3(0.0f, 0.0f, 0.0f), sum_raw = make_float3(0.0f, 0.0f, 0.0f);
  bp_u32 rays = 0u, nonfinite = 0u;
  for (bp_u32 s = 0u; s < params.samples_per_launch; ++s) {
    Rng rng = rng_init(params.seed, pixel, params.first_sample + s);
    float jx = rng_uniform(&rng), jy = rng_uniform(&rng);
    float3 dir = camera_ray_direction(&camera, px, py, jx, jy);
    PathRadiance l = trace_path(&scene, &params, origin, dir, &rng, &rays);
    // No NaN or Inf reaches the image: drop and count them.
    if (isfinite(l.weighted.x + l.weighted.y + l.weighted.z + l.raw.x + l.raw.y + l.raw.z)) {
      sum += l.weighted;
      sum_raw += l.raw;
    } else {
      nonfinite += 1u;
    }
  }
  __global PixelAccum* out = &accum[pixel];
  out->weighted[0] = sum.x; out->weighted[1] = sum.y; out->weighted[2] = sum.z;
  out->raw[0] = sum_raw.x; out->raw[1] = sum_raw.y; out->raw[2] = sum_raw.z;
  out->rays = rays;
  out->nonfinite_samples = nonfinite;
}

// The albedo a denoiser reads at a surface (docs/design.md §13): what it reflects of white light in
// [0, 1]. Modified Phong: kd + ks; glTF's model: the diffuse base under its Fresnel layer, the layer,
// and the metal's Schlick colour at n.wo.
static float3 surface_albedo(const Bsdf* bsdf, float cos_o) {
  if (!bsdf_is_ggx(bsdf)) return clamp(bsdf->kd + bsdf->ks, 0.0f, 1.0f);
  const MetallicRoughness* mr = &bsdf->metallic_roughness;
  const float w = schlick_weight(clamp(cos_o, 0.0f, 1.0f));
  const float f_dielectric = mr->specular_weight * schlick_scalar(bp_max3(mr->dielectric_f0), w);
  const float3 f_metal = mr->base_color + (make_float3(1.0f, 1.0f, 1.0f) - mr->base_color) * w;
  const float3 dielectric = mr->base_color * (1.0f - f_dielectric) + make_float3(f_dielectric, f_dielectric, f_dielectric);
  return clamp((dielectric * (1.0f - mr->metallic) + f_metal * mr->metallic) * mr->opaque, 0.0f, 1.0f);
}

// The first-hit features of one camera ray for a denoiser (docs/design.md §13): the albedo and the
// shading normal (world space, towards the eye) of the first surface that is not a delta vertex --
// through a pane's mirror, refractions and reflections of glass, to what is seen behind them, the
// albedo times what they pass on. A ray that leaves the scene: the environment clamped to [0, 1] as
// albedo, and no normal.
typedef struct {
  float3 albedo;
  float3 normal;
} FirstHitFeatures;

static FirstHitFeatures first_hit_features_of(const SceneRefs* scene, const PathTraceParams* params, float3 origin,
                                              float3 dir, Rng* rng) {
  FirstHitFeatures out;
  out.albedo = make_float3(0.0f, 0.0f, 0.0f);
  out.normal = make_float3(0.0f, 0.0f, 0.0f);
  float3 throughput = make_float3(1.0f, 1.0f, 1.0f);
  bp_u32 rays = 0u;
  for (bp_u32 depth = 0; depth < BP_DELTA_RUN_BEFORE_ROULETTE; ++depth) {
    Hit hit;
    bp_u32 pane_event;
    if (!closest_hit_through_panes(scene->nodes, scene->triangles, scene->shading, scene->materials,
                                   &scene->lights.textures, scene->alpha_masks, origin, dir, params->ray_epsilon, 1,
                                   rng, &throughput, &pane_event, &hit, &rays)) {
      out.albedo = throughput * clamp(environment_radiance(&scene->lights.environment, dir), 0.0f, 1.0f);
      return out;
    }
    SurfaceHit surface = surface_at_shaded(scene->shading, scene->cluster_fans, scene->shading_normals,
                                           params->shading_normals, &scene->lights.textures, scene->tangents,
                                           hit.triangle, hit.b1, hit.b2, origin + dir * hit.t, dir);
    int delta = BP_FEATURE_TRANSMISSION && pane_event == BP_PANE_MIRROR;
    if (delta) dir = reflect_about(-dir, surface.normal);
    BP_GLOBAL const Material* hit_material = &scene->materials[surface.material];
    if (BP_FEATURE_TRANSMISSION && !delta && (hit_material->flags & BP_MATERIAL_REFRACTOR)) {
      const int front = surface.reflects;
      const float rest = front || (hit_material->flags & BP_MATERIAL_DOUBLE_SIDED)
                             ? bsdf_from_material(hit_material).continuation : 0.0f;
      DielectricSample ds = dielectric_sample(-dir, surface.shading_normal, surface.normal, front, hit_material->ior,
                                              hit_material->transmission, bp_load3(hit_material->transmission_tint),
                                              rest, rng_uniform(rng));
      if (ds.event == BP_DIELECTRIC_ABSORBED) return out;
      throughput *= ds.factor;  // as the path tracer's walk: the rest's too (its 1 / probability)
      delta = ds.event != BP_DIELECTRIC_REST;
      if (delta) dir = ds.wi;
    }
    if (delta) {
      origin = surface.position + surface.normal * (dot(surface.normal, dir) > 0.0f ? params->ray_epsilon
                                                                                     : -params->ray_epsilon);
      continue;
    }
    Bsdf bsdf = pt_bsdf(scene, &surface, &hit);
    float3 albedo = surface_albedo(&bsdf, dot(surface.shading_normal, -dir));
    // An emitter of no albedo (a light's own surface): its colour, so the denoiser keeps its edges.
    if (albedo.x + albedo.y + albedo.z <= 0.0f && bp_max3(bsdf.emission) > 0.0f)
      albedo = bsdf.emission / bp_max3(bsdf.emission);
    out.albedo = throughput * albedo;
    out.normal = surface.shading_normal;
    return out;
  }
  return out;
}

// The first-hit albedo and normal of every pixel, box-filtered like the beauty: the mean over
// params.samples_per_launch^2 camera rays stratified over the pixel. features: 6 floats per pixel
// (albedo RGB, normal XYZ). The other arguments are the path tracer's, so that both share one
// program and one argument list.
__kernel void first_hit_features(__global const BvhNode* nodes, __global const BvhTriangle* triangles,
                                 __global const TriangleShading* shading, __global const Material* materials,
                                 __global const Light* lights, __global const float* light_cdf,
                                 const CameraParams camera, const PathTraceParams params, __global float* features,
                                 __global const LightTreeNode* light_tree,
                                 __global const LightReceiver* light_receivers, const uint light_selection,
                                 __global const float* shading_normals, __global const TextureView* texture_views,
                                 __global const uint* texels, __global const MaterialTextures* material_textures,
                                 __global const float* texcoords, __global const Material* patch_materials,
                                 const uint alpha_masks, __global const float* environment,
                                 __global const float* tangents, __global const ClusterFan* cluster_fans) {
  bp_u32 pixel = (bp_u32)get_global_id(0);
  if (pixel >= camera.width * camera.height) return;
  SceneRefs scene = {nodes, triangles, shading, cluster_fans, materials, shading_normals, tangents,
                     light_set(lights, light_cdf, light_tree, light_receivers, params.light_count, light_selection),
                     patch_materials, alpha_masks};
  const TextureSet textures = {texture_views, texels, material_textures, texcoords, params.uv_slots};
  scene.lights.textures = textures;
  scene.lights.environment = environment_map(environment, params.environment_width, params.environment_height);
  bp_u32 px = pixel % camera.width, py = pixel / camera.width;
  float3 origin = make_float3(camera.position[0], camera.position[1], camera.position[2]);
  float3 albedo = make_float3(0.0f, 0.0f, 0.0f), normal = make_float3(0.0f, 0.0f, 0.0f);
  const bp_u32 side = max(params.samples_per_launch, 1u);
  for (bp_u32 s = 0u; s < side * side; ++s) {
    Rng rng = rng_init(params.seed, pixel, s);
    float jx = ((float)(s % side) + rng_uniform(&rng)) / (float)side;
    float jy = ((float)(s / side) + rng_uniform(&rng)) / (float)side;
    FirstHitFeatures f = first_hit_features_of(&scene, &params, origin, camera_ray_direction(&camera, px, py, jx, jy),
                                               &rng);
    if (isfinite(f.albedo.x + f.albedo.y + f.albedo.z + f.normal.x + f.normal.y + f.normal.z)) {
      albedo += f.albedo;
      normal += f.normal;
    }
  }
  const float inv = 1.0f / (float)(side * side);
  albedo = clamp(albedo * inv, 0.0f, 1.0f);
  normal *= inv;
  __global float* out = &features[(size_t)pixel * 6u];
  out[0] = albedo.x; out[1] = albedo.y; out[2] = albedo.z;
  out[3] = normal.x; out[4] = normal.y; out[5] = normal.z;
}
