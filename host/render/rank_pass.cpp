#include "render/rank_pass.h"

#include <algorithm>

namespace bp {

std::uint32_t rank_chain_seed(std::uint32_t seed, int rank) {
  if (rank == 0) return seed;
  // A 64-bit finaliser (splitmix64) of (seed, rank): unrelated seeds for neighbouring ranks.
  std::uint64_t z = (std::uint64_t(seed) << 32 | std::uint32_t(rank)) + 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return std::uint32_t(z ^ (z >> 31));
}

RoundSlice rank_slice(std::uint64_t batch_first, std::uint32_t count, int rank, int ranks) {
  const std::uint64_t n = std::uint64_t(ranks), r = std::uint64_t(rank);
  return RoundSlice{batch_first + count * r / n, batch_first + count * (r + 1) / n};
}

RankPass::RankPass(ProgressivePass& pass, const Ranks& ranks, std::vector<RankSums> sums)
    : pass_(pass), ranks_(ranks), sums_(std::move(sums)) {}

BatchCounts RankPass::run(std::uint64_t first, std::uint32_t count) {
  const RoundSlice slice = rank_slice(first, count, ranks_.rank(), ranks_.size());
  for (const RankSums& s : sums_) s.rank->clear();
  BatchCounts counts;
  std::string failure;
  try {
    if (slice.end > slice.first) counts = pass_.run(slice.first, std::uint32_t(slice.end - slice.first));
  } catch (const PassFailure& e) {
    failure = e.what();
  }
  failure = ranks_.first_failure(failure);
  if (!failure.empty()) throw PassFailure(failure);
  rank_rounds_ += slice.end - slice.first;

  std::vector<std::uint64_t> totals{counts.rays, counts.fragments, counts.nonfinite_samples};
  for (const RankSums& s : sums_) {
    ranks_.sum_to_root(s.rank->sum);
    ranks_.sum_to_root(s.rank->raw_sum);
    totals.push_back(s.rank->samples_per_pixel);
  }
  ranks_.sum_to_root(totals);
  if (!ranks_.root()) return counts;  // this rank's part (root's figures are the render's)
  for (std::size_t k = 0; k < sums_.size(); ++k) {
    sums_[k].rank->samples_per_pixel = totals[3 + k];
    sums_[k].render->add(*sums_[k].rank);
  }
  return BatchCounts{totals[0], totals[1], totals[2]};
}

std::uint32_t RankPass::max_batch() const {
  const std::uint64_t batch = std::uint64_t(pass_.max_batch()) * std::uint64_t(ranks_.size());
  return std::uint32_t(std::min<std::uint64_t>(batch, 1u << 30));
}

}  // namespace bp
