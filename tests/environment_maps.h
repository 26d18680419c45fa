// Environment maps with analytic answers, for the environment tests (unit and kernel).
#pragma once
#include "scene/environment_map.h"

#include <cmath>

namespace bp::test {

// The upper half of the sky graded by column, the lower half brighter and flat (W 8, H 4: the
// horizon is the edge between rows 1 and 2).
inline EnvironmentImage graded_sky() {
  EnvironmentImage m;
  m.width = 8;
  m.height = 4;
  for (int row = 0; row < m.height; ++row)
    for (int column = 0; column < m.width; ++column) {
      const float l = row < 2 ? 0.2f + 0.3f * float(column) : 3.0f;
      m.rgb.insert(m.rgb.end(), {l, 0.5f * l, 0.25f * l});
    }
  return m;
}

// The irradiance of channel c on a plane facing +Y: the sum over the upper half's texels of L times
// the integral of cos(theta) over the texel, (2 pi / W) (sin^2 theta_1 - sin^2 theta_0) / 2.
inline double upward_irradiance(const EnvironmentImage& m, int c) {
  double e = 0.0;
  for (int row = 0; row < m.height / 2; ++row) {
    const double s0 = std::sin(M_PI * row / m.height), s1 = std::sin(M_PI * (row + 1) / m.height);
    for (int column = 0; column < m.width; ++column)
      e += m.rgb[(std::size_t(row) * m.width + column) * 3 + c] * (2.0 * M_PI / m.width) * 0.5 * (s1 * s1 - s0 * s0);
  }
  return e;
}

// The same radiance in every texel of a width x height map.
inline EnvironmentImage constant_environment(int width, int height, const float rgb[3]) {
  EnvironmentImage m;
  m.width = width;
  m.height = height;
  for (int i = 0; i < width * height; ++i) m.rgb.insert(m.rgb.end(), {rgb[0], rgb[1], rgb[2]});
  return m;
}

}  // namespace bp::test
