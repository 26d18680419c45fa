// The lights that light sampling chooses from (kernels/shared/lights.h), with their power.
#pragma once
#include "kernels/shared/lights.h"
#include "scene/bvh.h"
#include "scene/scene.h"
#include <vector>

namespace bp {

struct LightList {
  std::vector<Light> lights;              // emissive triangles (scene order), point and spot lights, directional ones, the environment
  std::vector<float> cdf;                 // cdf[i] = P(select one of lights 0..i); the last is 1
  std::vector<float> material_pdf_area;   // per scene material: P(select) / area of its emitters, m^-2
  std::vector<std::uint32_t> light_of_triangle;  // per scene triangle: its light, BP_NO_LIGHT if it emits nothing
  double total_power = 0.0;               // W, summed over the colour channels' mean
  std::uint32_t environment_light = BP_NO_LIGHT;  // the environment's index in lights (the last), if it has one
};

// Power of each light (Le pi A per emitting side; 4 pi I for a point; the cone's solid angle times
// I for a spot; E times sunlit_area for a directional light; pi r^2 times the integral of its
// radiance for the environment, what enters the scene's bounding sphere), and the list with its
// selection cdf. Empty when nothing emits. The powers only choose lights (select_probability, the
// light tree): any positive value keeps the estimate unbiased.
LightList build_light_list(const Scene& scene, const FlatBvh& bvh);

// The grid of sunlit_area's rays across the scene's bounding disk, per side.
constexpr int kSunlitGrid = 256;

// The area across a directional light travelling along `axis` whose rays first meet a surface's
// front (or a double-sided surface): a grid x grid lattice of parallel rays over the disk of the
// scene's bounding sphere, each cell counted where its centre's ray is. Off by at most one cell
// along each edge of what is lit (the cell is the disk's diameter / grid on a side).
double sunlit_area(const Scene& scene, const FlatBvh& bvh, const glm::vec3& axis, int grid);

}  // namespace bp
