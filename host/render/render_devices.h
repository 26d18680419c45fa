// The devices of a render (docs/design.md §8): which ones --device names, each opened with a copy of the
// scene, and which pass each one runs.
#pragma once
#include "device/device_context.h"
#include "device/device_scene.h"
#include "render/render_scene.h"

#include <memory>
#include <string>
#include <vector>

namespace bp {

// SPEC: comma-separated device indices or name substrings (as select_device takes one), or "all";
// empty: select_device's default. Throws UsageError for an empty item, "all" among others, or a
// device named twice; DeviceError (listing the devices) for an item that matches none.
std::vector<DeviceInfo> select_devices(const std::string& spec);

// One device of a render: its context and queue, and the scene uploaded to it.
struct RenderDevice {
  DeviceContext context;
  DeviceScene scene;
  RenderDevice(const DeviceInfo& info, const RenderScene& s, std::uint32_t light_selection)
      : context(info), scene(context, s.scene, s.patches, s.bvh, light_selection) {}
};

// Which device runs which pass: RB (whose iterations form one chain) on one device, PT on the
// others, split by sample index. One device runs both; --mode pt splits PT over every device;
// --mode rb uses the first device only.
struct DeviceRoles {
  std::vector<std::size_t> pt;  // indices into the render's devices
  std::size_t rb = 0;
  std::vector<std::size_t> idle;
};
DeviceRoles assign_device_roles(const std::string& mode, std::size_t device_count);

}  // namespace bp
