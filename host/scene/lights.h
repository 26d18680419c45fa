// The lights that light sampling chooses from (kernels/shared/lights.h), with their power.
#pragma once
#include "kernels/shared/lights.h"
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
// I for a spot; E pi r^2 for a directional light, what crosses the scene's bounding sphere; pi r^2
// times the integral of its radiance for the environment, what enters that sphere), and the
// list with its selection cdf. Empty when nothing emits.
LightList build_light_list(const Scene& scene);

}  // namespace bp
