#include "render/render_devices.h"

#include <algorithm>

namespace bp {

std::vector<DeviceInfo> select_devices(const std::string& spec) {
  if (spec == "all") return list_devices();
  if (spec.find(',') == std::string::npos) return {select_device(spec)};
  std::vector<DeviceInfo> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = spec.find(',', start);
    const std::string item = spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item.empty()) throw UsageError("--device '" + spec + "': an empty item (give indices or names, comma-separated)");
    if (item == "all") throw UsageError("--device '" + spec + "': 'all' stands alone, not in a list");
    DeviceInfo d = select_device(item);
    for (const DeviceInfo& seen : out)
      if (seen.index == d.index)
        throw UsageError("--device '" + spec + "': device [" + std::to_string(d.index) + "] " + d.device_name +
                         " is named twice");
    out.push_back(d);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

DeviceRoles assign_device_roles(const std::string& mode, std::size_t device_count) {
  DeviceRoles roles;
  if (device_count <= 1) {
    roles.pt = {0};
    return roles;
  }
  if (mode == "pt") {
    for (std::size_t i = 0; i < device_count; ++i) roles.pt.push_back(i);
  } else if (mode == "rb") {
    for (std::size_t i = 1; i < device_count; ++i) roles.idle.push_back(i);
  } else {
    for (std::size_t i = 1; i < device_count; ++i) roles.pt.push_back(i);
  }
  return roles;
}

}  // namespace bp
