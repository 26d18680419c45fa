#pragma once
// The global directions of the ray-bundle iterations, as points of the unit square (docs/design.md §2:
// omega = (sqrt(1 - z^2) cos phi, sqrt(1 - z^2) sin phi, z), z = 1 - 2 u1, phi = 2 pi u2, uniform on
// the sphere).
//
// Independent (the default): every iteration draws its point on its own, as in the paper. Stratified
// (experimental, --rb-directions stratified):
// the image iterations are cut into blocks of kStratifiedBlock; a block holds kStratifiedInterleave
// sequences, taken in turn (iteration j of the block belongs to sequence j mod L), and each sequence
// visits the kStratifiedCells cells of a 4 x 4 grid over the unit square once each, in a random order,
// at a uniform point inside the cell. Every iteration's point is still uniform on the square, and
// blocks and sequences are independent of each other, so
//   * any kStratifiedInterleave consecutive directions are independent: the chain's products of up
//     to L transfers (light carried over up to L bundle segments in a row) have exactly the
//     expectation of independent directions;
//   * what one direction decides alone — above all the light that reaches the eye from patches lit
//     by their own light samples, one transfer away — is averaged over stratified directions: on the
//     Lambert house at 160x90, 144 iterations, the image level's spread between seeds falls from
//     1.9 % to 0.8 % (README, issue #12);
//   * longer products take two directions of one sequence, which never share a cell; their
//     expectation differs from the independent one's by the spread between cells over the cells less
//     one (1/15), in paths of more than L bundle segments. That is a bias, and not a small one where
//     transfers depend sharply on the direction: two near-vertical segments four apart meet 7 % less
//     often than with independent directions. Measured on the Lambert house (README, "Stratified
//     ray-bundle directions"): image level -1.0 ± 0.8 % in the combination, -5.5 % in RB alone over two
//     30 s runs; hence not the default.
//   * a batch of the error estimate that holds whole blocks is independent of the other batches
//     (the default --error-batch, 64, is one block).
// The warm-up iterations draw independent directions; the blocks start at the first image iteration.

#include <cstdint>

namespace bp {

enum class DirectionSequence : std::uint32_t { independent, stratified };

constexpr std::uint32_t kStratifiedCellsPerSide = 4;
constexpr std::uint32_t kStratifiedCells = kStratifiedCellsPerSide * kStratifiedCellsPerSide;
constexpr std::uint32_t kStratifiedInterleave = 4;
constexpr std::uint32_t kStratifiedBlock = kStratifiedCells * kStratifiedInterleave;

struct UnitSquarePoint {
  float u1 = 0.0f, u2 = 0.0f;
};

// The point of `iteration` (counted from the first warm-up iteration; `warmup` of them come before the
// image's). `jitter` is the iteration's own two uniform numbers: the point itself (independent), or
// its place in its cell (stratified).
UnitSquarePoint bundle_direction_point(DirectionSequence sequence, std::uint32_t seed, std::uint64_t iteration,
                                       std::uint64_t warmup, UnitSquarePoint jitter);

// The cell of a stratified block's sequence that its `visit`-th iteration takes (0 .. kStratifiedCells-1);
// each cell once over the kStratifiedCells visits. `sequence_index` numbers the block's sequences over
// the whole render (block * kStratifiedInterleave + sequence).
std::uint32_t stratified_cell(std::uint32_t seed, std::uint64_t sequence_index, std::uint32_t visit);

}  // namespace bp
