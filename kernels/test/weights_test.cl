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
                           __global float* out) {
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
    path_pdf_step(&pdf, b.continuation, bsdf_pdf_uv(&b, n, wi, wo));
    if (mode == BP_WEIGHTS_PRODUCT) path_pdf_multiply_beta(&pdf, vertex_beta(&b, n, wi, wo, ratio));
  }
  float w_pt = pt_emission_weight(&pdf, mode, ratio);

  // RB: from the light towards the eye (bundle.cl): beta at every reflection (rb_outgoing, and
  // rb_eye for vertex 0), or eq. (10) from P = 1 at the emitter and the paper's weight at the eye.
  float w_rb = 1.0f, log_pstar = 0.0f;
  for (int k = (int)vertices - 1; k >= 0; --k) {
    Bsdf b = bsdf_from_material(&m[k]);
    float3 n = bp_load3(g + 9 * k), wo = bp_load3(g + 9 * k + 3), wi = bp_load3(g + 9 * k + 6);
    if (mode == BP_WEIGHTS_PRODUCT) w_rb *= vertex_beta(&b, n, wi, wo, ratio);
    log_pstar = paper_log_pstar_step(&b, n, wi, wo, log_pstar);
  }
  if (mode == BP_WEIGHTS_PAPER) w_rb = paper_rb_weight(log_pstar, ratio);
  if (mode == BP_WEIGHTS_NONE) w_rb = 1.0f;
  out[2 * path] = w_pt;
  out[2 * path + 1] = w_rb;
}
