// Test kernel: runs the shared BSDF sampler on the device so the host can chi-square its output
// and compare the returned pdf with the host-compiled pdf function.
#include "shared/types.h"
#include "shared/rng.h"
#include "shared/brdf.h"

// out[4*i..4*i+3] = (wi.x, wi.y, wi.z, pdf_uv returned by the sampler)
__kernel void sample_bsdf(__global const Material* material, const float wo_x, const float wo_y, const float wo_z,
                          const bp_u32 seed, const bp_u32 count, __global float* out) {
  bp_u32 i = (bp_u32)get_global_id(0);
  if (i >= count) return;
  Bsdf bsdf = bsdf_from_material(material);
  Rng rng = rng_init(seed, i, 0u);
  float u_lobe = rng_uniform(&rng), u1 = rng_uniform(&rng), u2 = rng_uniform(&rng);
  float3 n = make_float3(0.0f, 0.0f, 1.0f);
  BsdfSample s = bsdf_sample(&bsdf, n, normalize(make_float3(wo_x, wo_y, wo_z)), u_lobe, u1, u2);
  out[4 * i + 0] = s.wi.x;
  out[4 * i + 1] = s.wi.y;
  out[4 * i + 2] = s.wi.z;
  out[4 * i + 3] = s.pdf_uv;
}

#ifdef BP_TEST_BUILD_ERROR
// Lets the tests check that a failed build reports this file and line.
this_line_does_not_compile
#endif
