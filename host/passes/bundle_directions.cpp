#include "passes/bundle_directions.h"

#include "kernels/shared/rng.h"

#include <array>
#include <utility>

namespace bp {

namespace {
constexpr std::uint32_t kCellOrderStream = 0x5eed0b0du;  // RNG stream of the cells' visiting orders
}

std::uint32_t stratified_cell(std::uint32_t seed, std::uint64_t sequence_index, std::uint32_t visit) {
  // A uniformly random order of the cells (Fisher-Yates), one per sequence of a block.
  std::array<std::uint32_t, kStratifiedCells> order{};
  for (std::uint32_t k = 0; k < kStratifiedCells; ++k) order[k] = k;
  Rng rng = rng_init(seed, kCellOrderStream, std::uint32_t(sequence_index));
  for (std::uint32_t k = kStratifiedCells - 1; k > 0; --k) std::swap(order[k], order[rng_next_u32(&rng) % (k + 1)]);
  return order[visit % kStratifiedCells];
}

UnitSquarePoint bundle_direction_point(DirectionSequence sequence, std::uint32_t seed, std::uint64_t iteration,
                                       std::uint64_t warmup, UnitSquarePoint jitter) {
  if (sequence == DirectionSequence::independent || iteration < warmup) return jitter;
  const std::uint64_t j = iteration - warmup, block = j / kStratifiedBlock, in_block = j % kStratifiedBlock;
  const std::uint64_t sequence_index = block * kStratifiedInterleave + in_block % kStratifiedInterleave;
  const std::uint32_t cell = stratified_cell(seed, sequence_index, std::uint32_t(in_block / kStratifiedInterleave));
  const float side = float(kStratifiedCellsPerSide);
  return {(float(cell % kStratifiedCellsPerSide) + jitter.u1) / side,
          (float(cell / kStratifiedCellsPerSide) + jitter.u2) / side};
}

}  // namespace bp
