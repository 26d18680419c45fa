// Counter-based RNG: Philox4x32-10 (Salmon et al., "Parallel random numbers: as easy as 1, 2, 3",
// SC'11). A sample is a pure function of (seed, pixel, sample index, draw index), so the same seed
// gives a bit-identical image on the same device whatever the launch sizes.
#ifndef BP_SHARED_RNG_H
#define BP_SHARED_RNG_H
#include "shared/compat.h"

typedef struct {
  bp_u32 key[2];   // (seed, stream): stream is the pixel, or any other independent id
  bp_u32 ctr[2];   // (sample index, block of four draws)
  bp_u32 out[4];
  bp_u32 used;     // draws consumed from out
} Rng;

BP_FN void philox4x32_10(const bp_u32 key_in[2], const bp_u32 ctr_in[4], bp_u32 out[4]) {
  bp_u32 k0 = key_in[0], k1 = key_in[1];
  bp_u32 c0 = ctr_in[0], c1 = ctr_in[1], c2 = ctr_in[2], c3 = ctr_in[3];
  for (int round = 0; round < 10; ++round) {
    bp_u32 hi0 = bp_mulhi(0xD2511F53u, c0), lo0 = 0xD2511F53u * c0;
    bp_u32 hi1 = bp_mulhi(0xCD9E8D57u, c2), lo1 = 0xCD9E8D57u * c2;
    bp_u32 n0 = hi1 ^ c1 ^ k0, n2 = hi0 ^ c3 ^ k1;
    c0 = n0; c1 = lo1; c2 = n2; c3 = lo0;
    k0 += 0x9E3779B9u; k1 += 0xBB67AE85u;
  }
  out[0] = c0; out[1] = c1; out[2] = c2; out[3] = c3;
}

BP_FN Rng rng_init(bp_u32 seed, bp_u32 stream, bp_u32 sample_index) {
  Rng r;
  r.key[0] = seed; r.key[1] = stream;
  r.ctr[0] = sample_index; r.ctr[1] = 0u;
  r.out[0] = r.out[1] = r.out[2] = r.out[3] = 0u;
  r.used = 4u;
  return r;
}

BP_FN bp_u32 rng_next_u32(Rng* r) {
  if (r->used == 4u) {
    bp_u32 ctr[4];
    ctr[0] = r->ctr[0]; ctr[1] = r->ctr[1]; ctr[2] = 0u; ctr[3] = 0u;
    philox4x32_10(r->key, ctr, r->out);
    r->ctr[1] += 1u;
    r->used = 0u;
  }
  return r->out[r->used++];
}

// Uniform in [0, 1): the top 24 bits, so 1.0f is never returned.
BP_FN float rng_uniform(Rng* r) { return (float)(rng_next_u32(r) >> 8) * (1.0f / 16777216.0f); }

#endif  // BP_SHARED_RNG_H
