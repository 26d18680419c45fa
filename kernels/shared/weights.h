// The combination weights of DESIGN.md §3, defined once and included by both estimators' kernels.
// ratio = N2 / N1 (RB iterations per PT sample per pixel). Every density is in the uv measure (eq. 7).
#ifndef BP_SHARED_WEIGHTS_H
#define BP_SHARED_WEIGHTS_H
#include "shared/brdf.h"
#include "shared/compat.h"
#include "shared/path_pdf.h"

// The PT density, with Russian roulette, of the direction wi that continues the path from a vertex
// whose eye side is wo -- the one-step quantity of eq. (10): (1 - s) + s p_uv(wi | wo).
BP_FN float vertex_pt_density(const Bsdf* b, float3 n, float3 wi, float3 wo) {
  return (1.0f - b->continuation) + b->continuation * bsdf_pdf_uv(b, n, wi, wo);
}

// beta of a vertex (DESIGN.md §3, product weights): the paper's balance weight of one step,
// beta = N2 / (N2 + N1 P), P = (1 - s) + s p_uv(wi | wo). RB multiplies it in when it reflects and
// at the eye; PT multiplies the same product along its walk: w_RB = prod beta, w_PT = 1 - prod beta.
// The heuristic lives here alone, so variants can be measured against each other.
BP_FN float vertex_beta(const Bsdf* b, float3 n, float3 wi, float3 wo, float ratio_n2_over_n1) {
  float p = vertex_pt_density(b, n, wi, wo);
  return ratio_n2_over_n1 / (ratio_n2_over_n1 + p);
}

BP_FN float log_or_zero(float x) { return x > 0.0f ? log(x) : BP_LOG_ZERO; }

// One step of eq. (10) at a vertex that reflects light arriving from wi towards wo,
// P = s p_uv(wi | wo) P_prev + (1 - s), on ln P: P passes 1e38 on long paths through sharp lobes.
// Taken from the light towards the eye it gives exactly PT's q + r (eq. 9) of the same directions.
BP_FN float paper_log_pstar_step(const Bsdf* b, float3 n, float3 wi, float3 wo, float log_pstar_prev) {
  float s = b->continuation;
  return log_add_exp(log_or_zero(s) + log_or_zero(bsdf_pdf_uv(b, n, wi, wo)) + log_pstar_prev, log_or_zero(1.0f - s));
}

// The paper's RB weight (eq. 4 with P* from eq. 10): w_RB = N2 / (N1 P* + N2), as a logistic of
// ln(N1 P* / N2) -- the complement of pt_emission_weight's, so the two sum to one.
BP_FN float paper_rb_weight(float log_pstar, float ratio_n2_over_n1) {
  return 1.0f / (1.0f + exp(log_pstar - log(ratio_n2_over_n1)));
}

#endif  // BP_SHARED_WEIGHTS_H
