// Shared by the kernel tests: the first PoCL/CPU device, and a render of a Scene through exactly
// the path the CLI takes (patches, BVH, upload, PathTracerPass, render loop).
#pragma once
#include "device/device_context.h"
#include "image/image.h"
#include "passes/render_loop.h"
#include "scene/scene.h"
#include <memory>

namespace bp::test {

const DeviceContext& test_device();

struct RenderRun {
  ImageRGB image;
  RenderOutcome outcome;
};

RenderRun render_pt(const Scene& scene, int width, int height, std::uint64_t spp, std::uint32_t seed,
                    std::uint32_t max_depth = 65536);

// A closed axis-aligned box [-h,h]^3 seen from inside: 12 triangles facing inwards, one material.
Scene make_closed_box(float half_size, const SceneMaterial& material);

}  // namespace bp::test
