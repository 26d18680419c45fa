// Scenes made from a seed, for benchmarks and convergence studies: no files needed.
#pragma once
#include "scene/scene.h"

#include <cstddef>
#include <cstdint>

namespace bp {

// n triangles scattered in the unit cube [0,1]^3, random orientation, edges ~ 6/sqrt(n) so a ray
// across the cube crosses a few of them; about 1 in 64 is emissive. Camera outside, facing -z.
Scene make_random_triangles_scene(std::size_t n, std::uint32_t seed);

// A grid of rooms_per_side² rooms of 5 m x 4 m x 2.8 m (rooms_per_side 0: one room per ~4000
// triangles wanted, rooms_for_triangles): walls with doorways, furniture boxes, one emissive ceiling
// panel per room (2 triangles, facing down). Walls, floors, ceilings and boxes are tessellated into
// squares so the count comes close to target_triangles: with the rooms fixed, a larger target is the
// same house (layout, lights, camera) cut finer. Interior walls are double-sided. Camera in room
// (0, 0), eye height 1.6 m.
Scene make_rooms_scene(std::size_t target_triangles, std::uint32_t seed, int rooms_per_side = 0);

// The rooms per side make_rooms_scene picks for a triangle count: round(sqrt(n / 4000)), at least 1.
int rooms_for_triangles(std::size_t target_triangles);

}  // namespace bp
