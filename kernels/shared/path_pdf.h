// The PT pdf state of a path prefix, q and r of eq. (9), and the weight hooks of docs/design.md §3.
// Kept in the log domain: q is a product of up to hundreds of factors, some above 1e4 for sharp
// lobes, so it would overflow or underflow in plain float.
#ifndef BP_SHARED_PATH_PDF_H
#define BP_SHARED_PATH_PDF_H
#include "shared/compat.h"
#include "shared/types.h"

#define BP_LOG_ZERO (-1.0e30f)

typedef struct {
  float log_q;             // ln q: density of the prefix with the walk still alive
  float log_r;             // ln r: density of the prefixes that Russian roulette ended (uniform tail)
  float beta_product;      // prod beta of the product weights (docs/design.md §3); 1 = empty product. Each
                           // beta is in [0, 1], so it cannot overflow; underflow to 0 is its limit
                           // (w_RB = 0), which RB's own products reach alike
} PathPdf;

// ln(e^a + e^b) without overflow.
BP_FN float log_add_exp(float a, float b) {
  float hi = fmax(a, b), lo = fmin(a, b);
  if (lo <= BP_LOG_ZERO) return hi;
  return hi + log1p(exp(lo - hi));
}

BP_FN PathPdf path_pdf_start(void) {
  PathPdf p;
  p.log_q = 0.0f;          // q_0 = 1   (9)
  p.log_r = BP_LOG_ZERO;   // r_0 = 0   (9)
  p.beta_product = 1.0f;
  return p;
}

// One vertex: continuation probability s, PT density pdf_uv of the sampled direction.
BP_FN void path_pdf_step(PathPdf* p, float continuation, float pdf_uv) {
  float log_q_prev = p->log_q;
  float log_terminated = continuation < 1.0f ? log(1.0f - continuation) + log_q_prev : BP_LOG_ZERO;
  p->log_r = log_add_exp(log_terminated, p->log_r);                  // r_k = (1-s) q_{k-1} + r_{k-1}  (9)
  p->log_q = log(continuation) + log(pdf_uv) + log_q_prev;           // q_k = s p q_{k-1}               (9)
}

// One vertex's beta of the product weights (kernels/shared/weights.h). Not a logarithm: PoCL's log()
// per vertex made the weighted path tracer 17 % slower than PT alone.
BP_FN void path_pdf_multiply_beta(PathPdf* p, float beta) { p->beta_product *= beta; }

// ln P* = ln(q + r), the prefix density when ended walks continue uniformly (eq. 8).
BP_FN float path_pdf_log_pstar(const PathPdf* p) { return log_add_exp(p->log_q, p->log_r); }

// The weight PT gives an emission picked up after this prefix. ratio = N2/N1.
// BP_WEIGHTS_NONE: PT alone, weight 1. BP_WEIGHTS_PAPER: w_PT = N1 P*/(N1 P* + N2)  (4),
// written as a logistic of ln(N1 P*/N2) so it never overflows.
BP_FN float pt_emission_weight(const PathPdf* p, bp_u32 mode, float ratio_n2_over_n1) {
  if (mode == BP_WEIGHTS_PAPER) {
    float x = path_pdf_log_pstar(p) - log(ratio_n2_over_n1);
    return 1.0f / (1.0f + exp(-x));
  }
  if (mode == BP_WEIGHTS_PRODUCT) return 1.0f - p->beta_product;  // w_PT = 1 - prod beta
  return 1.0f;
}

#endif  // BP_SHARED_PATH_PDF_H
