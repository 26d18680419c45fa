// Light selection that knows where the lights are (docs/design.md §3): a BVH over the lights whose nodes
// bound power, position and a cone of normals (Conty & Kulla 2018, as pbrt-v4's BVHLightSampler),
// walked from the root with, at each node, the children chosen by their importance for the
// receiver. The receiver is a patch (centroid, flat normal, bounding radius), not a point, so PT and
// RB, which both know the receiving patch, evaluate the same selection probability.
#ifndef BP_SHARED_LIGHT_TREE_H
#define BP_SHARED_LIGHT_TREE_H
#include "shared/compat.h"

#define BP_LIGHT_NODE_LEAF 1u       // `child` is the first of `leaf_lights` lights, not the second child
#define BP_LIGHT_NODE_TWO_SIDED 2u  // some light below emits from both sides: angles are taken up to sign

#define BP_NO_LIGHT 0xffffffffu

// One node; host/scene/light_tree.cpp builds them depth first (the first child follows its parent).
typedef struct {
  float lo[3];
  float power;          // of the lights below, as a fraction of the scene's (the root's is 1)
  float hi[3];
  float cos_theta_o;    // the lights' normals lie within theta_o of axis
  float axis[3];
  float cos_theta_e;    // each light emits within theta_e of its normal (pi/2 for area lights)
  bp_u32 child;         // interior: the second child's index; leaf: its first light's index
  bp_u32 flags;         // BP_LIGHT_NODE_*
  float receiver_offset;  // the rays' offset off a receiving patch, m (the same in every node)
  bp_u32 leaf_lights;     // leaf: its lights, child .. child + leaf_lights - 1 (one panel's triangles)
} LightTreeNode;

// A receiving patch as light selection sees it; one per patch, the same buffer for PT and RB.
typedef struct {
  float centroid[3];
  float radius;         // every point of the patch (plus the rays' offset) lies within it of centroid
  float normal[3];      // the patch's flat front normal
  bp_u32 light;         // the light this patch is part of (an emissive triangle's side), BP_NO_LIGHT
  float infinite_visibility;  // how much of the directional lights and the environment reaches the
                              // patch, in (0, 1]: scales their share of its choice (lights.h)
  float pad[3];
} LightReceiver;

// cos and sin of max(0, a - b) given those of a and b (angles in [0, pi]).
BP_FN void light_cone_subtract(float cos_a, float sin_a, float cos_b, float sin_b, float* cos_out, float* sin_out) {
  if (cos_a >= cos_b) {  // a <= b
    *cos_out = 1.0f;
    *sin_out = 0.0f;
  } else {
    *cos_out = cos_a * cos_b + sin_a * sin_b;
    *sin_out = sin_a * cos_b - cos_a * sin_b;
  }
}

// Importance of a node's lights for a receiving patch: power times the cosines of the smallest
// angles that the bounds allow, at the light and at the receiver, over the squared distance. Zero
// only where no point of the patch can see the front of any light below (both angle bounds hold for
// every pair of points: the directions between the two bounding spheres lie within theta_b of the
// line between their centres), with a margin for rounding; never zero otherwise.
BP_FN float light_node_importance(BP_GLOBAL const LightTreeNode* node, float3 centroid, float radius, float3 normal) {
  const float margin = 1e-3f, plane_margin = 1e-4f, floor_cos = 1e-3f;  // margins for rounding: in cos, in radii
  float3 lo = bp_load3(node->lo), hi = bp_load3(node->hi);
  float3 to_node = (lo + hi) * 0.5f - centroid;
  float3 half_size = (hi - lo) * 0.5f;
  float node_radius = sqrt(dot(half_size, half_size)), reach = node_radius + radius;
  float d2 = dot(to_node, to_node);
  float d = sqrt(d2);
  // The bounding spheres overlap: every direction is possible, no angle can cull.
  float sin_b = 1.0f, cos_b = 0.0f;
  float3 dir = make_float3(0.0f, 0.0f, 0.0f);
  int overlap = !(d > reach);
  if (!overlap) {
    sin_b = reach / d;
    cos_b = sqrt(fmax(0.0f, 1.0f - sin_b * sin_b));
    dir = to_node / d;
  }
  // The patch is flat: it sees only what lies above its plane (up to the margin).
  float above = dot(normal, to_node) + fabs(normal.x) * half_size.x + fabs(normal.y) * half_size.y + fabs(normal.z) * half_size.z;
  if (above < -plane_margin * radius) return 0.0f;
  // One-sided lights that all face one way (a panel): some point of the patch must be in front of
  // some point of the bounds; the patch reaches radius along the part of axis in its plane, and
  // the rays' offset off it.
  float3 axis = bp_load3(node->axis);
  if (node->cos_theta_o >= 1.0f && node->cos_theta_e <= 0.0f && !(node->flags & BP_LIGHT_NODE_TWO_SIDED)) {
    float along = dot(axis, normal);
    float front = -dot(axis, to_node) + fabs(axis.x) * half_size.x + fabs(axis.y) * half_size.y + fabs(axis.z) * half_size.z +
                  radius * sqrt(fmax(0.0f, 1.0f - along * along)) + 2.0f * node->receiver_offset;
    if (front < -plane_margin * radius) return 0.0f;
  }
  float receiver_cos = 1.0f, light_cos = 1.0f;
  if (!overlap) {
    // Receiver: the patch sees a point only in front of it: theta_i - theta_b < pi/2.
    float cos_i = clamp(dot(normal, dir), -1.0f, 1.0f), sin_i = sqrt(fmax(0.0f, 1.0f - cos_i * cos_i));
    float c, s;
    light_cone_subtract(cos_i, sin_i, cos_b, sin_b, &c, &s);
    if (c < -margin) return 0.0f;
    receiver_cos = fmax(c, floor_cos);
    // Light: some normal within theta_o of the axis must face the receiver within theta_e:
    // theta_w - theta_o - theta_b < theta_e.
    float cos_w = clamp(-dot(axis, dir), -1.0f, 1.0f);
    if (node->flags & BP_LIGHT_NODE_TWO_SIDED) cos_w = fabs(cos_w);
    float sin_w = sqrt(fmax(0.0f, 1.0f - cos_w * cos_w));
    float cos_o = node->cos_theta_o, sin_o = sqrt(fmax(0.0f, 1.0f - cos_o * cos_o));
    float cx, sx, cp, sp;
    light_cone_subtract(cos_w, sin_w, cos_o, sin_o, &cx, &sx);
    light_cone_subtract(cx, sx, cos_b, sin_b, &cp, &sp);
    if (cp < node->cos_theta_e - margin) return 0.0f;
    light_cos = fmax(cp, floor_cos);
  }
  // The distance to the centre, but no less than the sizes involved (it is a heuristic: any
  // positive number keeps the estimate unbiased).
  d2 = fmax(d2, fmax(node_radius * node_radius, radius * radius));
  d2 = fmax(d2, 1e-30f);
  return node->power * light_cos * receiver_cos / d2;
}

// Probability of the first child of interior node `node` (the second has 1 - that). Where neither
// child matters for the receiver, by power (then 1/2): the probabilities over all lights always
// sum to one, and a light no point of the patch can see contributes nothing when chosen.
BP_FN float light_tree_first_probability(BP_GLOBAL const LightTreeNode* nodes, bp_u32 node, float3 centroid,
                                         float radius, float3 normal) {
  BP_GLOBAL const LightTreeNode* first = &nodes[node + 1u];
  BP_GLOBAL const LightTreeNode* second = &nodes[nodes[node].child];
  float a = light_node_importance(first, centroid, radius, normal);
  float b = light_node_importance(second, centroid, radius, normal);
  if (!(a + b > 0.0f) || !BP_ISFINITE(a + b)) {
    a = first->power;
    b = second->power;
  }
  if (!(a + b > 0.0f) || !BP_ISFINITE(a + b)) return 0.5f;
  return a / (a + b);
}

// A leaf reached for a receiver, the probability it was reached with, and what is left of u.
typedef struct {
  bp_u32 node;
  float probability;
  float u;
} LightTreeLeaf;

// Walks from the root: child by importance, u reused (rescaled into the chosen interval).
BP_FN LightTreeLeaf light_tree_select(BP_GLOBAL const LightTreeNode* nodes, BP_GLOBAL const LightReceiver* receiver,
                                      float u) {
  float3 c = bp_load3(receiver->centroid), n = bp_load3(receiver->normal);
  float r = receiver->radius;
  LightTreeLeaf pick;
  pick.probability = 1.0f;
  bp_u32 node = 0u;
  while (!(nodes[node].flags & BP_LIGHT_NODE_LEAF)) {
    float p = light_tree_first_probability(nodes, node, c, r, n);
    if (u < p) {
      pick.probability *= p;
      u = u / p;
      node = node + 1u;
    } else {
      pick.probability *= 1.0f - p;
      u = (u - p) / (1.0f - p);
      node = nodes[node].child;
    }
    u = fmin(fmax(u, 0.0f), 0.99999994f);  // [0, 1) again despite rounding
  }
  pick.node = node;
  pick.u = u;
  return pick;
}

// Probability that light_tree_select reaches the leaf at the end of `trail` (bit k set: the second
// child at depth k), for the same receiver: the same products in the same order. *leaf: that leaf.
BP_FN float light_tree_probability(BP_GLOBAL const LightTreeNode* nodes, BP_GLOBAL const LightReceiver* receiver,
                                   bp_u32 trail_lo, bp_u32 trail_hi, bp_u32 depth, bp_u32* leaf) {
  float3 c = bp_load3(receiver->centroid), n = bp_load3(receiver->normal);
  float r = receiver->radius;
  float probability = 1.0f;
  bp_u32 node = 0u;
  for (bp_u32 k = 0u; k < depth; ++k) {
    float p = light_tree_first_probability(nodes, node, c, r, n);
    bp_u32 second = ((k < 32u ? trail_lo >> k : trail_hi >> (k - 32u)) & 1u);
    if (second == 0u) {
      probability *= p;
      node = node + 1u;
    } else {
      probability *= 1.0f - p;
      node = nodes[node].child;
    }
  }
  *leaf = node;
  return probability;
}

#endif  // BP_SHARED_LIGHT_TREE_H
