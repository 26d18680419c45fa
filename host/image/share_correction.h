// The ray bundles' share of the image made consistent by the path tracer's estimate of the same
// share (--rb-level consistent, the default; docs/design.md §13).
//
// RB's weighted layer r estimates its share of every path with patch-level light, so E[r] is off by a
// discretisation bias b that more iterations do not remove. PT's unweighted less weighted samples,
// d = u − w, estimate the same share without bias but with PT's noise. Over a block B of pixels, the
// two block means combine best (least squared error, the two independent) as
//
//   R_B = r_B + λ (d_B − r_B),   λ = (b² + V_r) / (b² + V_r + V_d)                     (shrinkage)
//
// and E[(d_B − r_B)²] = b² + V_r + V_d, so λ = 1 − V_d / E[(d_B − r_B)²] (below: with a threshold κ): it needs PT's variance of
// the block mean V_d (its pixels are independent: the sum of theirs over n²) and the squared
// residual, pooled over the block and its eight neighbours (a single block's is one noisy sample).
// A pyramid of blocks, coarse to fine (kShareCorrectionBlocks), each level correcting what the
// coarser ones left, the corrections interpolated bilinearly between block centres (no seams), ends
// at single pixels. As the render goes on V_d falls as 1/N while b stays, so λ → 1 wherever RB is
// biased and every pixel's share converges to PT's unbiased one; where RB is exact λ follows the two
// variances and RB's low noise is kept. No factor is clamped.
//
// What is left at a pixel after the last level is its share's error: (1 − λ)² times the residual's
// mean square beyond PT's noise (b² + V_r, pooled; not clamped at 0, so that over the image the
// residuals' noise cancels), which the render's error estimate reports along
// with PT's variance (set_share_correction in image/error_estimate.h). The pixel level's residual
// reads d(p) through the coarser levels' block means only with weight at most 1/16 (the finest block
// before single pixels is 4x4), so the check is all but independent of what it checks.
#pragma once
#include "image/image.h"

#include <array>
#include <vector>

namespace bp {

// λ = 1 − κ V_d / E[(d_B − r_B)²] with κ = kShareCorrectionThreshold: a block is corrected only where
// its pooled residual's mean square is κ times PT's noise or more (twice its amplitude: nine pooled
// blocks of pure noise reach it with probability 2e-5), so PT's noise does not leak into RB's share
// where RB is right; still λ → 1 wherever RB is biased, as V_d → 0. κ = 1 (the least-squares λ,
// its noise unaccounted) lets PT's noise into RB's exact share and over-reports what it leaves
// (tests/unit/test_share_correction.cpp fails with it); κ = 4 passes them.
constexpr double kShareCorrectionThreshold = 4.0;

// The pyramid's block edges in pixels, coarse to fine; 1 is the pixel level. The pixel level corrects
// only where the last block level (4x4) did: pixels' pooled residuals cross the threshold by chance
// far more often than blocks' (PT's noise per pixel is heavy-tailed, and its variance there rests on
// few batches), and each such crossing puts PT's noise into an unbiased pixel. Without the gate the
// Lambert house at 7 spp + 224 iterations had 1.6x the variance of --rb-level regional, with it 0.9x
// and the same blocks (docs/results.md, "Denoised images"). Consistency then holds wherever RB's bias does not cancel
// exactly inside every 4x4 block of a 12x12-pixel neighbourhood.
constexpr std::array<int, 5> kShareCorrectionBlocks = {32, 16, 8, 4, 1};

struct ShareCorrection {
  ImageRGB share;                   // the corrected share: what the image adds to PT's weighted layer
  std::vector<double> lambda;       // per pixel, the pixel level's λ (1: PT's estimate of the share alone; 0 gated)
  std::vector<double> left_error;   // per pixel and channel, (1 − λ)² (pooled residual² − V_d): may be < 0
};

// rb: RB's share as the image has it so far (its weighted layer, --rb-level regional's field
// applied); d: PT's estimate of the same share (its unweighted less weighted mean); d_variance: per
// pixel and channel, the variance of d's mean (empty or NaN: unknown, and rb is returned as it is).
ShareCorrection correct_share(const ImageRGB& rb, const ImageRGB& d, const std::vector<double>& d_variance);

}  // namespace bp
