// The combination weights of docs/design.md §3, defined once and included by both estimators' kernels.
// ratio = N2 / N1 (RB iterations per PT sample per pixel). Every density is in the uv measure (eq. 7).
#ifndef BP_SHARED_WEIGHTS_H
#define BP_SHARED_WEIGHTS_H
#include "shared/brdf.h"
#include "shared/compat.h"
#include "shared/path_pdf.h"

// beta of a vertex (docs/design.md §3, product weights), from P = (1 - s) + s p_uv(wi | wo), the PT density,
// with Russian roulette, of the direction wi that continues the path from a vertex whose eye side is
// wo (the one-step quantity of eq. 10), against RB's density 1, with N1 and N2 samples:
//   BP_BETA_BALANCE: beta = N2 / (N2 + N1 P), the paper's balance weight of one step (--beta
//                    balance). A path of k diffuse vertices gets about (N2 / (N2 + N1))^k: RB loses
//                    long paths even where it samples them as well as PT.
//   BP_BETA_CLAMPED: beta = min(1, N2 / (N1 P)): RB keeps the whole vertex wherever its sample density
//                    is at least PT's, and the share above it; the product no longer decays along
//                    diffuse paths. Lower relMSE at equal time on every scene measured (README).
// RB multiplies it in when it reflects and at the eye; PT multiplies the same product along its walk:
// w_RB = prod beta, w_PT = 1 - prod beta, exact for any beta in [0, 1] both sides compute alike. Callers
// pass p_uv(wi | wo) from bsdf_evaluate (the path tracer: from bsdf_sample, which returns the same
// number), so the lobe is evaluated once.
BP_FN float vertex_beta(float continuation, float pdf_uv, float ratio_n2_over_n1, bp_u32 heuristic) {
  float pt_density = (1.0f - continuation) + continuation * pdf_uv;
  if (heuristic == BP_BETA_BALANCE) return ratio_n2_over_n1 / (ratio_n2_over_n1 + pt_density);
  return pt_density <= ratio_n2_over_n1 ? 1.0f : ratio_n2_over_n1 / pt_density;
}

BP_FN float log_or_zero(float x) { return x > 0.0f ? log(x) : BP_LOG_ZERO; }

// One step of eq. (10) at a vertex that reflects light arriving from wi towards wo (continuation s,
// p_uv(wi | wo) from bsdf_evaluate), P = s p_uv(wi | wo) P_prev + (1 - s), on ln P: P passes 1e38 on
// long paths through sharp lobes. Taken from the light towards the eye it gives exactly PT's q + r
// (eq. 9) of the same directions.
BP_FN float paper_log_pstar_step(float continuation, float pdf_uv, float log_pstar_prev) {
  float s = continuation;
  return log_add_exp(log_or_zero(s) + log_or_zero(pdf_uv) + log_pstar_prev, log_or_zero(1.0f - s));
}

// The paper's RB weight (eq. 4 with P* from eq. 10): w_RB = N2 / (N1 P* + N2), as a logistic of
// ln(N1 P* / N2) -- the complement of pt_emission_weight's, so the two sum to one.
BP_FN float paper_rb_weight(float log_pstar, float ratio_n2_over_n1) {
  return 1.0f / (1.0f + exp(log_pstar - log(ratio_n2_over_n1)));
}

// The four techniques that can make the last segment of a path (the connection from x_{n-1} to the
// emitter) when light sampling is on (docs/design.md §3, "Light sampling as a strategy"): RB bundle
// (density 1, N2 samples), RB per-patch light sample (p_L, rho N2: a patch samples the lights in an
// iteration with probability rho, the rate), PT BSDF (s p_b, N1), PT light sample (p_L, N1). With
// D = N2 (1 + rho p_L) + N1 (s p_b + p_L) and the product prefix_beta of the vertices before x_{n-1}:
//   w_RB,bundle = prefix_beta N2 / D,  w_RB,light = prefix_beta rho N2 p_L / D,  R = their sum,
//   w_PT,bsdf = (1 - R) s p_b / (s p_b + p_L),  w_PT,light = (1 - R) p_L / (s p_b + p_L).
// prefix_beta = 0 gives PT alone its balance heuristic: the eye vertex's direct light, or
// --weights none. A delta light (p_L infinite) splits rho N2 : N1 between the two light samples.
typedef struct {
  float rb_bundle, rb_light, pt_bsdf, pt_light;
} LastSegmentWeights;

// A delta light (point, spot, directional: p_L infinite) is reached by the two light samples alone.
// PT's picks it with probability p_select (N1 per pixel); RB's per-patch sample picks it with the
// same p_select and, under --rb-sun own, takes rb_own_samples more of it (1 for each directional
// light) in every iteration, all at the rate rho (rho N2). With c = rho N2 / N1 the balance split is
//   w_RB,light = prefix_beta c (p_select + own) / (c (p_select + own) + p_select),  w_PT,light = 1 - w_RB,light,
// and each RB sample of the light counts 1 / (p_select + own) of it (rb_delta_sample_share). Without
// own samples: c / (c + 1) for any p_select, the split PT and RB always had.
BP_FN LastSegmentWeights delta_light_weights(float prefix_beta, float ratio_n2_over_n1, float rb_light_rate,
                                             float p_select, float rb_own_samples) {
  LastSegmentWeights w;
  float rb = ratio_n2_over_n1 * rb_light_rate * (p_select + rb_own_samples);
  w.rb_bundle = 0.0f;
  w.pt_bsdf = 0.0f;
  w.rb_light = rb > 0.0f ? prefix_beta * rb / (rb + p_select) : 0.0f;
  w.pt_light = 1.0f - w.rb_light;
  return w;
}

// What one of RB's samples of a delta light counts of its estimate L cos / (rho p_select): p_select
// of the p_select + own samples a patch takes of it per iteration at the rate (delta_light_weights).
BP_FN float rb_delta_sample_share(float p_select, float rb_own_samples) {
  return rb_own_samples > 0.0f ? p_select / (p_select + rb_own_samples) : 1.0f;
}

// The four-technique split with RB's share R computed from pdf_bsdf_share in the place of PT's BSDF
// density, and PT's own share 1 - R split between its two techniques by its true density
// pdf_bsdf_pt (the balance heuristic). The four weights sum to one for any pdf_bsdf_share, so a
// density RB can evaluate without the view direction may stand in for PT's there (the eye vertex,
// docs/design.md §3 "Sharing the eye vertex's direct light with RB").
BP_FN LastSegmentWeights last_segment_split(float prefix_beta, float ratio_n2_over_n1, float rb_light_rate,
                                            float pdf_bsdf_share, float pdf_bsdf_pt, float pdf_light_uv,
                                            int is_delta) {
  if (is_delta) return delta_light_weights(prefix_beta, ratio_n2_over_n1, rb_light_rate, 1.0f, 0.0f);
  LastSegmentWeights w;
  w.rb_bundle = 0.0f;
  // Every term of D divided by m = max(1, s p_b, p_L) and by N1, so nothing overflows for sharp
  // lobes or lights seen at grazing angles.
  float m = fmax(1.0f, fmax(pdf_bsdf_share, pdf_light_uv));
  float share = pdf_bsdf_share / m, light = pdf_light_uv / m, c = ratio_n2_over_n1;
  float d = c * (1.0f / m + rb_light_rate * light) + share + light;
  w.rb_bundle = d > 0.0f ? prefix_beta * (c / m) / d : 0.0f;
  w.rb_light = d > 0.0f ? prefix_beta * (c * rb_light_rate * light) / d : 0.0f;
  float pt_share = fmax(0.0f, 1.0f - (w.rb_bundle + w.rb_light));  // not -1e-8 where RB takes it all
  float mp = fmax(pdf_bsdf_pt, pdf_light_uv);
  float bsdf = mp > 0.0f ? pdf_bsdf_pt / mp : 0.0f, light_pt = mp > 0.0f ? pdf_light_uv / mp : 0.0f;
  float pt_sum = bsdf + light_pt;
  w.pt_bsdf = pt_sum > 0.0f ? pt_share * bsdf / pt_sum : 0.5f * pt_share;
  w.pt_light = pt_sum > 0.0f ? pt_share * light_pt / pt_sum : 0.5f * pt_share;
  return w;
}

// The last segment of a path from vertex x_{n-1} (not the eye vertex), both sides with PT's true
// s p_b of the direction towards the light given the one x_{n-1} sends to.
BP_FN LastSegmentWeights last_segment_weights(float prefix_beta, float ratio_n2_over_n1, float rb_light_rate,
                                              float pdf_bsdf_uv, float pdf_light_uv, int is_delta) {
  return last_segment_split(prefix_beta, ratio_n2_over_n1, rb_light_rate, pdf_bsdf_uv, pdf_bsdf_uv, pdf_light_uv,
                            is_delta);
}

// The view-independent stand-in for PT's s p_b(wi | w_view) at the eye vertex, which RB must evaluate
// per fragment and per shadow ray before any pixel exists: s (P_d 2 cos theta_in + P_s (n + 1)), the
// diffuse part of the mixture exactly and the Phong lobe at its peak (its largest density over all
// views). Exact for Lambert surfaces (DESIGN.md's p~_b); on glossy ones it leans to PT, which samples
// the lobe that RB's patch-level direct light would blur. GGX lobes change with the view: there an
// upper bound over every view (metallic_roughness_eye_proxy_pdf_uv).
BP_FN float eye_direct_proxy_pdf_uv(const Bsdf* b, float cos_theta_in) {
  if (!(cos_theta_in > 0.0f)) return 0.0f;
  if (bsdf_is_ggx(b)) return metallic_roughness_eye_proxy_pdf_uv(&b->metallic_roughness, b->continuation, cos_theta_in);
  float lobe_peak = BP_FEATURE_PHONG ? (1.0f - b->p_diffuse) * (b->shininess + 1.0f) : 0.0f;
  return b->continuation * (b->p_diffuse * pdf_uv_cosine(cos_theta_in) + lobe_peak);
}

// The proxy of the eye vertex's material itself (its factors), not of its patch's texture means: RB
// spreads its eye-vertex weights over neighbouring patches (Gouraud corners), and PT's pixel must
// read the same number as every neighbour of one material, whatever the texels (for untextured
// materials the two are the same). Used by both sides for --eye-direct shared.
BP_FN float eye_direct_material_proxy_pdf_uv(BP_GLOBAL const Material* m, float cos_theta_in) {
  Bsdf b = bsdf_from_material(m);
  return eye_direct_proxy_pdf_uv(&b, cos_theta_in);
}

// The eye vertex's direct light shared between the four techniques (docs/design.md §3, "Sharing the eye
// vertex's direct light with RB"): the empty prefix, RB's share from the proxy density, PT's split
// by its true one:
//   D~ = N2 (1 + rho p_L) + N1 (p~_b + p_L),  w_RB,bundle = N2 / D~,  w_RB,light = rho N2 p_L / D~,
//   w_PT,bsdf = (1 - R) s p_b / (s p_b + p_L),  w_PT,light = (1 - R) p_L / (s p_b + p_L).
BP_FN LastSegmentWeights eye_segment_weights(float ratio_n2_over_n1, float rb_light_rate, float pdf_proxy_uv,
                                             float pdf_bsdf_uv, float pdf_light_uv, int is_delta) {
  return last_segment_split(1.0f, ratio_n2_over_n1, rb_light_rate, pdf_proxy_uv, pdf_bsdf_uv, pdf_light_uv,
                            is_delta);
}

#endif  // BP_SHARED_WEIGHTS_H
