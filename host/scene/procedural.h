// Scenes made from a seed, for benchmarks and convergence studies: no files needed.
#pragma once
#include "scene/scene.h"

#include <cstddef>
#include <cstdint>

namespace bp {

// n triangles scattered in the unit cube [0,1]^3, random orientation, edges ~ 6/sqrt(n) so a ray
// across the cube crosses a few of them; about 1 in 64 is emissive. Camera outside, facing -z.
Scene make_random_triangles_scene(std::size_t n, std::uint32_t seed);

// A grid of 5 m x 4 m x 2.8 m rooms (one per ~4000 triangles wanted): walls with doorways,
// furniture boxes, one emissive ceiling panel per room (2 triangles, facing down). Walls,
// floors, ceilings and boxes are tessellated into squares so the count comes close to
// target_triangles. Interior walls are double-sided. Camera in room (0, 0), eye height 1.6 m.
Scene make_rooms_scene(std::size_t target_triangles, std::uint32_t seed);

}  // namespace bp
