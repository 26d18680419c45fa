// The shading normal a view can use (docs/design.md §6). Interpolated normals lean away from the
// geometric one (a smooth-shaded cylinder's rim averages its cap's and its side's; a normal map at
// a grazing view), and a viewer can then be behind the shading normal while in front of the surface.
#ifndef BP_SHARED_VIEW_NORMAL_H
#define BP_SHARED_VIEW_NORMAL_H
#include "shared/compat.h"

// A lobe around the mirror direction (glossy) is black where the viewer `wo` is behind ns. Cycles'
// answer, followed here (ensure_valid_specular_reflection in its kernel): where the mirror of wo
// about ns would dip below the surface, or rise less than t = min(0.9 wo.ng, 0.01) above it, bend
// ns toward ng in the plane of the two until that mirror is exactly t above the surface. With N = x X + z ng (X: ns's part
// along the surface, normalised) and R = 2 (N.wo) N - wo, R.ng = t is
//   4 a z^4 - 2 b z^2 + c = 0,  a = (wo.X)^2 + (wo.ng)^2,  b = 2 (a + t wo.ng),  c = (t + wo.ng)^2,
// whose root on the side of wo's tangential part is taken. Then N.wo > 0: the view is in front.
BP_FN float3 valid_reflection_normal(float3 ng, float3 wo, float3 ns) {
  const float iz = dot(wo, ng);
  if (!(iz > 0.0f)) return ns;  // a view from behind the surface itself: nothing to bend toward
  const float t = fmin(0.9f * iz, 0.01f);
  if (dot(ng, ns * (2.0f * dot(ns, wo)) - wo) >= t) return ns;
  const float3 along = ns - ng * dot(ns, ng);
  const float len = length(along);
  if (!(len > 1e-7f)) return ns;
  const float3 x = along / len;
  const float ix = dot(wo, x);
  const float a = ix * ix + iz * iz, b = 2.0f * (a + iz * t), c = (t + iz) * (t + iz);
  const float root = sqrt(fmax(b * b - 4.0f * a * c, 0.0f));
  const float z2 = clamp(0.25f * (ix < 0.0f ? b + root : b - root) / a, 0.0f, 1.0f);
  return x * sqrt(1.0f - z2) + ng * sqrt(z2);
}

#endif  // BP_SHARED_VIEW_NORMAL_H
