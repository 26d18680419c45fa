// Test kernel: the weight that the PT code and the weight that the RB code give the same path, each
// computed the way its own kernel does (pathtrace.cl walks from the eye; bundle.cl reflects from the
// light towards the eye and takes the eye vertex last).
#include "shared/types.h"
#include "shared/brdf.h"
#include "shared/path_pdf.h"
#include "shared/weights.h"

// A path of `vertices` reflections, vertex 0 at the eye. Per vertex k: material[k] and the unit
// vectors n, wo (towards the eye side) and wi (towards the light side) at geometry[9k .. 9k+8].
// out[2 * path] = w_PT, out[2 * path + 1] = w_RB.
__kernel void path_weights(__global const Material* materials, __global const float* geometry,
                           const uint vertices, const uint paths, const uint mode, const float ratio,
                           const uint heuristic, __global float* out) {
  uint path = (uint)get_global_id(0);
  if (path >= paths) return;
  __global const Material* m = &materials[path * vertices];
  __global const float* g = &geometry[path * vertices * 9];

  // PT: q, r and the beta product along the walk from the eye (pathtrace.cl), then the weight of the
  // emission found after the last vertex.
  PathPdf pdf = path_pdf_start();
  for (uint k = 0; k < vertices; ++k) {
    Bsdf b = bsdf_from_material(&m[k]);
    float3 n = bp_load3(g + 9 * k), wo = bp_load3(g + 9 * k + 3), wi = bp_load3(g + 9 * k + 6);
    float pdf_uv = bsdf_pdf_uv(&b, n, wi, wo);  // what bsdf_sample returns with the direction
    if (mode == BP_WEIGHTS_PAPER) path_pdf_step(&pdf, b.continuation, pdf_uv);
    if (mode == BP_WEIGHTS_PRODUCT)
      path_pdf_multiply_beta(&pdf, vertex_beta(b.continuation, pdf_uv, ratio, heuristic));
  }
  float w_pt = pt_emission_weight(&pdf, mode, ratio);

  // RB: from the light towards the eye (bundle.cl): beta at every reflection (rb_outgoing, and
  // rb_eye for vertex 0), or eq. (10) from P = 1 at the emitter and the paper's weight at the eye.
  float w_rb = 1.0f, log_pstar = 0.0f;
  for (int k = (int)vertices - 1; k >= 0; --k) {
    Bsdf b = bsdf_from_material(&m[k]);
    float3 n = bp_load3(g + 9 * k), wo = bp_load3(g + 9 * k + 3), wi = bp_load3(g + 9 * k + 6);
    float pdf_uv = bsdf_evaluate(&b, n, wi, wo).pdf_uv;
    if (mode == BP_WEIGHTS_PRODUCT) w_rb *= vertex_beta(b.continuation, pdf_uv, ratio, heuristic);
    log_pstar = paper_log_pstar_step(b.continuation, pdf_uv, log_pstar);
  }
  if (mode == BP_WEIGHTS_PAPER) w_rb = paper_rb_weight(log_pstar, ratio);
  if (mode == BP_WEIGHTS_NONE) w_rb = 1.0f;
  out[2 * path] = w_pt;
  out[2 * path + 1] = w_rb;
}

// With light sampling (docs/design.md §3): the four techniques of the last segment. The path's vertices
// are as above, the last one (k = vertices - 1) connecting to the light; pdf_light[path] is the
// light-sampling density of that connection (uv), is_delta[path] marks a point or spot light (1) or
// a sun that RB's patches also sample on their own (2, --rb-sun own: pdf_light is then the sun's
// selection probability; delta_light_weights at every vertex but the eye's).
// out[4 * path ..] = w_PT,bsdf, w_PT,light (as pathtrace.cl computes them), w_RB,bundle, w_RB,light
// (as bundle.cl does: the last vertex's factor in rb_tile_resolve / rb_light_sample, then beta at
// every reflection towards the eye, none of it at the eye vertex itself). eye_shared: a one-vertex
// path's direct light is split as --eye-direct shared does (pathtrace.cl: eye_segment_weights with
// PT's true density; bundle.cl: the same with the proxy only, in rb_direct_received / rb_outgoing).
__kernel void last_segment_path_weights(__global const Material* materials, __global const float* geometry,
                                        __global const float* pdf_light, __global const uint* is_delta,
                                        const uint vertices, const uint paths, const float ratio,
                                        const uint heuristic, const float light_rate, const uint eye_shared,
                                        __global float* out) {
  uint path = (uint)get_global_id(0);
  if (path >= paths) return;
  __global const Material* m = &materials[path * vertices];
  __global const float* g = &geometry[path * vertices * 9];
  const uint last = vertices - 1u;
  Bsdf bl = bsdf_from_material(&m[last]);
  float3 nl = bp_load3(g + 9 * last), wol = bp_load3(g + 9 * last + 3), wil = bp_load3(g + 9 * last + 6);
  float pdf_bsdf = bl.continuation * bsdf_pdf_uv(&bl, nl, wil, wol);

  // PT: beta of the vertices before the last along the walk from the eye, none for the eye vertex.
  PathPdf pdf = path_pdf_start();
  for (uint k = 0; k < last; ++k) {
    Bsdf b = bsdf_from_material(&m[k]);
    float3 n = bp_load3(g + 9 * k), wo = bp_load3(g + 9 * k + 3), wi = bp_load3(g + 9 * k + 6);
    path_pdf_multiply_beta(&pdf, vertex_beta(b.continuation, bsdf_pdf_uv(&b, n, wi, wo), ratio, heuristic));
  }
  float prefix = last == 0u ? 0.0f : pdf.beta_product;
  float proxy = eye_direct_proxy_pdf_uv(&bl, dot(nl, wil));
  const int own_sun = is_delta[path] == 2u && last > 0u;
  LastSegmentWeights pt = last_segment_weights(prefix, ratio, light_rate, pdf_bsdf, pdf_light[path], (int)is_delta[path]);
  if (own_sun) pt = delta_light_weights(prefix, ratio, light_rate, pdf_light[path], 1.0f);
  if (last == 0u && eye_shared)
    pt = eye_segment_weights(ratio, light_rate, proxy, pdf_bsdf, pdf_light[path], (int)is_delta[path]);

  // RB: the last vertex's factor, then beta at each reflection towards the eye (rb_outgoing), and at
  // the eye vertex (rb_eye), which takes no direct light at all.
  LastSegmentWeights rb = last_segment_weights(1.0f, ratio, light_rate, pdf_bsdf, pdf_light[path], (int)is_delta[path]);
  if (own_sun) rb = delta_light_weights(1.0f, ratio, light_rate, pdf_light[path], 1.0f);
  float rb_bundle = rb.rb_bundle, rb_light = rb.rb_light;
  for (int k = (int)last - 1; k >= 0; --k) {
    Bsdf b = bsdf_from_material(&m[k]);
    float3 n = bp_load3(g + 9 * k), wo = bp_load3(g + 9 * k + 3), wi = bp_load3(g + 9 * k + 6);
    float beta = vertex_beta(b.continuation, bsdf_evaluate(&b, n, wi, wo).pdf_uv, ratio, heuristic);
    rb_bundle *= beta;
    rb_light *= beta;
  }
  if (last == 0u && !eye_shared) rb_bundle = rb_light = 0.0f;
  if (last == 0u && eye_shared) {
    LastSegmentWeights eye = eye_segment_weights(ratio, light_rate, proxy, 0.0f, pdf_light[path], (int)is_delta[path]);
    rb_bundle = eye.rb_bundle;
    rb_light = eye.rb_light;
  }
  out[4 * path + 0] = pt.pt_bsdf;
  out[4 * path + 1] = pt.pt_light;
  out[4 * path + 2] = rb_bundle;
  out[4 * path + 3] = rb_light;
}
