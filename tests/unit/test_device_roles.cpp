// Several devices (docs/design.md §8): which device runs which pass, and --ratio auto's round when PT and
// RB run at the same time.
#include "render/parallel_pass.h"
#include "render/render_devices.h"

#include <gtest/gtest.h>

namespace bp {
namespace {

TEST(DeviceRoles, OneDeviceRunsBothPasses) {
  const DeviceRoles roles = assign_device_roles("combined", 1);
  EXPECT_EQ(roles.pt, std::vector<std::size_t>{0});
  EXPECT_EQ(roles.rb, 0u);
  EXPECT_TRUE(roles.idle.empty());
}

TEST(DeviceRoles, CombinedPutsRayBundlesOnTheFirstAndPathTracingOnTheOthers) {
  const DeviceRoles roles = assign_device_roles("combined", 3);
  EXPECT_EQ(roles.rb, 0u);
  EXPECT_EQ(roles.pt, (std::vector<std::size_t>{1, 2}));
  EXPECT_TRUE(roles.idle.empty());
}

TEST(DeviceRoles, PathTracingAloneUsesEveryDeviceAndRayBundlesAloneOne) {
  EXPECT_EQ(assign_device_roles("pt", 2).pt, (std::vector<std::size_t>{0, 1}));
  const DeviceRoles rb = assign_device_roles("rb", 2);
  EXPECT_TRUE(rb.pt.empty());
  EXPECT_EQ(rb.rb, 0u);
  EXPECT_EQ(rb.idle, std::vector<std::size_t>{1});
}

TEST(ConcurrentRatio, BalancesTheTwoDevicesTimePerRound) {
  // c = t_RB / t_PT: N1 t_PT = N2 t_RB.
  EXPECT_EQ(concurrent_ratio_shape(1.0, 3.0).pt_samples, 3u);
  EXPECT_EQ(concurrent_ratio_shape(1.0, 3.0).rb_iterations, 1u);
  EXPECT_EQ(concurrent_ratio_shape(4.0, 1.0).rb_iterations, 4u);
  EXPECT_EQ(concurrent_ratio_shape(4.0, 1.0).pt_samples, 1u);
  // Between two integers: the nearer in log (sqrt(2) = 1.414 is the boundary between 1 and 2).
  EXPECT_EQ(concurrent_ratio_shape(1.0, 1.39).pt_samples, 1u);
  EXPECT_EQ(concurrent_ratio_shape(1.0, 1.43).pt_samples, 2u);
  EXPECT_EQ(concurrent_ratio_shape(1.43, 1.0).rb_iterations, 2u);
  // Clamped as auto_ratio_shape: [1/1024, 64].
  EXPECT_EQ(concurrent_ratio_shape(1.0, 1e6).pt_samples, 64u);
  EXPECT_EQ(concurrent_ratio_shape(1e6, 1.0).rb_iterations, 1024u);
}

}  // namespace
}  // namespace bp
