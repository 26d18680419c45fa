// The environment light (--environment, docs/design.md §6) as an equirectangular radiance map: +Y up as
// glTF, the image's centre column looking along -Z, u growing towards +X (to the right of a viewer
// looking along -Z), v = 0 the top row (+Y). A uniform environment is the 1x1 map. Lookup is nearest
// texel, so the sampling density below is exactly proportional to luminance x sin(theta) per texel.
// Sampling: a piecewise-constant 2D distribution over the image (marginal cdf over rows, one
// conditional cdf per row), built on the host (host/scene/environment_map.cpp), the same buffer on
// both compilers:
//   [0, H]                 marginal cdf over rows, cdf[0] = 0, cdf[H] = 1
//   [H + 1, ...)           per row j its conditional cdf over columns, W + 1 values each
//   after them             the texels, RGB, row-major, top row first
#ifndef BP_SHARED_ENVIRONMENT_MAP_H
#define BP_SHARED_ENVIRONMENT_MAP_H
#include "shared/compat.h"

typedef struct {
  BP_GLOBAL const float* data;  // the layout above
  bp_u32 width, height;         // 0 x 0: no environment
} EnvironmentMap;

BP_FN EnvironmentMap environment_map(BP_GLOBAL const float* data, bp_u32 width, bp_u32 height) {
  EnvironmentMap m;
  m.data = data;
  m.width = BP_FEATURE_ENVIRONMENT ? width : 0u;
  m.height = BP_FEATURE_ENVIRONMENT ? height : 0u;
  return m;
}

// Floats of the packed map: both cdfs, then the texels.
BP_FN bp_u32 environment_cdf_floats(bp_u32 width, bp_u32 height) { return (height + 1u) + height * (width + 1u); }
BP_FN bp_u32 environment_packed_floats(bp_u32 width, bp_u32 height) {
  return environment_cdf_floats(width, height) + 3u * width * height;
}

// The direction of image point (u, v) in [0,1]^2: theta = pi v from +Y, phi = 2 pi (u - 1/2) from -Z
// towards +X: d = (sin theta sin phi, cos theta, -sin theta cos phi).
BP_FN float3 environment_direction(float u, float v) {
  float theta = BP_PI * v, phi = BP_TWO_PI * (u - 0.5f);
  float sin_theta = sin(theta);
  return make_float3(sin_theta * sin(phi), cos(theta), -sin_theta * cos(phi));
}

// The inverse of environment_direction for a unit direction: u = phi / 2 pi + 1/2, v = theta / pi.
BP_FN void environment_uv(float3 d, float* u, float* v) {
  *v = acos(clamp(d.y, -1.0f, 1.0f)) * BP_INV_PI;
  *u = atan2(d.x, -d.z) * (0.5f * BP_INV_PI) + 0.5f;
}

// The texel (column, row) that holds image point (u, v).
BP_FN bp_u32 environment_cell(float t, bp_u32 cells) {
  float c = floor(t * (float)cells);
  return c <= 0.0f ? 0u : (c >= (float)(cells - 1u) ? cells - 1u : (bp_u32)c);
}

BP_FN float3 environment_texel(const EnvironmentMap* m, bp_u32 column, bp_u32 row) {
  return bp_load3(m->data + environment_cdf_floats(m->width, m->height) + 3u * (row * m->width + column));
}

// Radiance arriving from direction d (towards the environment), nearest texel; black without a map.
BP_FN float3 environment_radiance(const EnvironmentMap* m, float3 d) {
  if (m->width == 0u) return make_float3(0.0f, 0.0f, 0.0f);
  float u, v;
  environment_uv(d, &u, &v);
  return environment_texel(m, environment_cell(u, m->width), environment_cell(v, m->height));
}

// The piecewise-constant density over the image square of cell (column, row):
// pdf_image = P(row) H * P(column | row) W.
BP_FN float environment_pdf_image(const EnvironmentMap* m, bp_u32 column, bp_u32 row) {
  BP_GLOBAL const float* marginal = m->data;
  BP_GLOBAL const float* conditional = m->data + (m->height + 1u) + row * (m->width + 1u);
  return (marginal[row + 1u] - marginal[row]) * (float)m->height * (conditional[column + 1u] - conditional[column]) *
         (float)m->width;
}

// Solid-angle density of sampling direction d: pdf_image / (2 pi^2 sin theta), the Jacobian of
// (u, v) -> direction being dω = 2 pi^2 sin theta du dv. 0 at the poles and without a map.
BP_FN float environment_pdf_solid_angle(const EnvironmentMap* m, float3 d) {
  if (m->width == 0u) return 0.0f;
  float u, v;
  environment_uv(d, &u, &v);
  float sin_theta = sqrt(d.x * d.x + d.z * d.z);  // not sqrt(1 - y^2), which cancels near the poles
  if (!(sin_theta > 0.0f)) return 0.0f;
  return environment_pdf_image(m, environment_cell(u, m->width), environment_cell(v, m->height)) /
         (2.0f * BP_PI * BP_PI * sin_theta);
}

// The interval i of a cdf over n cells that holds x in [0, 1): the first with x < cdf[i + 1] (so a
// cell of probability 0 is never chosen).
BP_FN bp_u32 environment_cdf_find(BP_GLOBAL const float* cdf, bp_u32 n, float x) {
  bp_u32 lo = 0u, hi = n - 1u;
  while (lo < hi) {
    bp_u32 mid = (lo + hi) / 2u;
    if (x < cdf[mid + 1u]) hi = mid; else lo = mid + 1u;
  }
  return lo;
}

// Where x falls within cell i of the cdf, in [0, 1).
BP_FN float environment_cdf_offset(BP_GLOBAL const float* cdf, bp_u32 i, float x) {
  float width = cdf[i + 1u] - cdf[i];
  return width > 0.0f ? fmin(fmax((x - cdf[i]) / width, 0.0f), 0.99999994f) : 0.5f;
}

typedef struct {
  float3 wi;              // towards the environment
  float3 radiance;        // L(wi)
  float pdf_solid_angle;  // 0: no sample (a pole, or no map)
} EnvironmentSample;

// A direction by the map's luminance x sin(theta): a row by the marginal cdf (u1), a column in it by
// its conditional cdf (u2), uniform within the cell.
BP_FN EnvironmentSample environment_sample(const EnvironmentMap* m, float u1, float u2) {
  EnvironmentSample s;
  s.wi = make_float3(0.0f, 1.0f, 0.0f);
  s.radiance = make_float3(0.0f, 0.0f, 0.0f);
  s.pdf_solid_angle = 0.0f;
  if (m->width == 0u) return s;
  BP_GLOBAL const float* marginal = m->data;
  bp_u32 row = environment_cdf_find(marginal, m->height, u1);
  BP_GLOBAL const float* conditional = m->data + (m->height + 1u) + row * (m->width + 1u);
  bp_u32 column = environment_cdf_find(conditional, m->width, u2);
  float v = ((float)row + environment_cdf_offset(marginal, row, u1)) / (float)m->height;
  float u = ((float)column + environment_cdf_offset(conditional, column, u2)) / (float)m->width;
  s.wi = environment_direction(u, v);
  float sin_theta = sin(BP_PI * v);
  if (!(sin_theta > 0.0f)) return s;
  s.radiance = environment_texel(m, column, row);
  s.pdf_solid_angle = environment_pdf_image(m, column, row) / (2.0f * BP_PI * BP_PI * sin_theta);
  return s;
}

#endif  // BP_SHARED_ENVIRONMENT_MAP_H
