// Path tracer megakernel (DESIGN.md §5): one work-item per pixel, samples_per_launch samples each.
// The loop calls stage functions: camera ray, intersect, surface, emission weight, sample, step.
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/camera.h"
#include "shared/bvh.h"
#include "shared/surface.h"
#include "shared/brdf.h"
#include "shared/path_pdf.h"
#include "shared/weights.h"

typedef struct {
  BP_GLOBAL const BvhNode* nodes;
  BP_GLOBAL const BvhTriangle* triangles;
  BP_GLOBAL const TriangleShading* shading;
  BP_GLOBAL const Material* materials;
} SceneRefs;

typedef struct {
  float3 weighted;  // each emission times w_PT of its prefix
  float3 raw;       // unweighted
} PathRadiance;

// Radiance of one path (one pixel sample). Counts the rays it traces.
static PathRadiance trace_path(const SceneRefs* scene, const PathTraceParams* params, float3 origin, float3 dir,
                               Rng* rng, bp_u32* rays) {
  PathRadiance radiance;
  radiance.weighted = make_float3(0.0f, 0.0f, 0.0f);
  radiance.raw = make_float3(0.0f, 0.0f, 0.0f);
  float3 throughput = make_float3(1.0f, 1.0f, 1.0f);
  PathPdf pdf = path_pdf_start();
  for (bp_u32 depth = 0; depth < params->max_depth; ++depth) {
    Hit hit;
    *rays += 1u;
    if (!bvh_closest_hit(scene->nodes, scene->triangles, origin, dir, BP_FLOAT_MAX, &hit)) break;
    SurfaceHit surface = surface_at(scene->shading, hit.triangle, hit.b1, hit.b2, origin + dir * hit.t, dir);
    if (!surface.reflects && !(scene->materials[surface.material].flags & BP_MATERIAL_DOUBLE_SIDED)) break;
    Bsdf bsdf = bsdf_from_material(&scene->materials[surface.material]);
    float3 wo = -dir;

    // Emission picked up after this prefix, weighted with w_PT of the prefix (DESIGN.md §3).
    float3 emitted = throughput * bsdf.emission;
    radiance.raw += emitted;
    radiance.weighted += emitted * pt_emission_weight(&pdf, params->weight_mode, params->weight_ratio);

    // Russian roulette on the material-only continuation probability s.
    if (rng_uniform(rng) >= bsdf.continuation) break;
    float u_lobe = rng_uniform(rng), u1 = rng_uniform(rng), u2 = rng_uniform(rng);
    BsdfSample sample = bsdf_sample(&bsdf, surface.normal, wo, u_lobe, u1, u2);
    if (sample.pdf_uv <= 0.0f) break;
    float cos_theta = dot(surface.normal, sample.wi);
    // f cos / (s p_solid_angle), with p_solid_angle = pdf_uv / 2 pi  (7)
    throughput *= bsdf_eval(&bsdf, surface.normal, sample.wi, wo) *
                  (cos_theta * BP_TWO_PI / (bsdf.continuation * sample.pdf_uv));
    path_pdf_step(&pdf, bsdf.continuation, sample.pdf_uv);
    if (params->weight_mode == BP_WEIGHTS_PRODUCT)
      path_pdf_multiply_beta(&pdf, vertex_beta(&bsdf, surface.normal, sample.wi, wo, params->weight_ratio));
    origin = surface.position + surface.normal * params->ray_epsilon;
    dir = sample.wi;
  }
  return radiance;
}

__kernel void pathtrace(__global const BvhNode* nodes, __global const BvhTriangle* triangles,
                        __global const TriangleShading* shading, __global const Material* materials,
                        const CameraParams camera, const PathTraceParams params,
                        __global PixelAccum* accum) {
  bp_u32 pixel = (bp_u32)get_global_id(0);
  if (pixel >= camera.width * camera.height) return;
  SceneRefs scene = {nodes, triangles, shading, materials};
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
