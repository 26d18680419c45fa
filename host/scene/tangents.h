// Tangents for glTF normal maps where a primitive has no TANGENT (glTF 2.0: "client implementations
// SHOULD calculate tangents using default MikkTSpace algorithms").
#pragma once
#include <glm/glm.hpp>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace bp {

struct GeneratedTangents {
  std::vector<glm::vec4> tangents;  // per vertex: xyz unit and orthogonal to its normal, w the handedness +-1
  std::size_t fallbacks = 0;        // vertices whose UVs gave no direction: any orthonormal tangent, w +1
};

// Per-vertex tangents of an indexed triangle list: each triangle's direction of increasing u (T) and
// of decreasing v (B: glTF's uv origin is the image's top-left, and a normal map's +Y points up the
// image), both projected into the plane of each corner's normal and summed with the corner's angle
// as weight over every triangle that shares the vertex (by index); then T Gram-Schmidt against the
// vertex normal and w = sign(dot(cross(n, T), B)). This is MikkTSpace's accumulation, and on typical
// meshes its answer; it is not MikkTSpace bit for bit where MikkTSpace splits a vertex (a seam of
// mirrored UVs, or triangles of opposite handedness sharing an index). Normals of any length.
GeneratedTangents generate_tangents(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                                    const std::vector<glm::vec2>& uvs,
                                    const std::vector<std::array<std::uint32_t, 3>>& triangles);

// Any unit tangent orthogonal to unit n (Duff et al. 2017's branchless basis).
glm::vec3 any_tangent(const glm::vec3& n);

}  // namespace bp
