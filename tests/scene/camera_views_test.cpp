// The views of a walkthrough on the host (scene/camera_views.h): the loader's camera nodes and their
// animation, animation sampling (LINEAR, STEP, clamping), the sample times, and view selection.
#include "scene/camera_views.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace bp {
namespace {

using test::test_file;

void expect_vec3_near(const glm::vec3& a, const glm::vec3& b, float tol = 1e-6f) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol) << "component " << i;
}

glm::dvec4 about_y(double degrees) {
  const double half = degrees * M_PI / 360.0;
  return glm::dvec4(0.0, std::sin(half), 0.0, std::cos(half));
}

// Looking down -z rotated by `degrees` about y: (-sin, 0, -cos).
glm::vec3 forward_about_y(double degrees) {
  const double a = degrees * M_PI / 180.0;
  return glm::vec3(float(-std::sin(a)), 0.0f, float(-std::cos(a)));
}

TEST(CameraViews, LoaderListsCameraNodesInSceneOrderWithTheirAnimation) {
  const Scene s = load_gltf(test_file("good/cornell-walk.gltf"));
  ASSERT_EQ(s.camera_nodes.size(), 3u);
  EXPECT_EQ(s.camera_nodes[0].name, "camera");
  EXPECT_EQ(s.camera_nodes[1].name, "left");
  EXPECT_EQ(s.camera_nodes[2].name, "walker");
  EXPECT_FALSE(s.camera_nodes[0].animation);
  EXPECT_FALSE(s.camera_nodes[1].animation);
  ASSERT_TRUE(s.camera_nodes[2].animation);
  expect_vec3_near(s.camera.position, s.camera_nodes[0].view.position);  // the plain render's view
  expect_vec3_near(s.camera_nodes[2].view.position, {0.278f, 0.273f, -0.6f});  // rig's +0.1 in x
  expect_vec3_near(s.camera_nodes[1].view.forward, forward_about_y(200.0), 1e-5f);
  const CameraAnimation& a = *s.camera_nodes[2].animation;
  EXPECT_EQ(a.name, "animation 0 \"walk\"");
  ASSERT_TRUE(a.translation_track && a.rotation_track);
  EXPECT_FALSE(a.translation_track->step);
  EXPECT_TRUE(a.rotation_track->step);
  EXPECT_EQ(a.start(), 0.0);
  EXPECT_EQ(a.end(), 1.0);
  EXPECT_EQ(s.node_names.size(), 8u);
}

SceneCameraNode rotating_node(bool step) {
  SceneCameraNode node;
  node.view.yfov = 0.5f;
  CameraAnimation a;
  a.name = "test";
  a.translation = glm::dvec3(1.0, 2.0, 3.0);
  CameraTrack rotation;
  rotation.times = {1.0, 2.0};
  rotation.values = {about_y(0.0), about_y(90.0)};
  rotation.step = step;
  a.rotation_track = rotation;
  node.animation = a;
  return node;
}

TEST(CameraViews, LinearRotationIsSlerpAndClampsOutsideItsKeys) {
  const SceneCameraNode node = rotating_node(false);
  expect_vec3_near(sample_camera_animation(node, 1.5).forward, forward_about_y(45.0));
  expect_vec3_near(sample_camera_animation(node, 1.25).forward, forward_about_y(22.5));
  expect_vec3_near(sample_camera_animation(node, 0.0).forward, forward_about_y(0.0));  // before the first key
  expect_vec3_near(sample_camera_animation(node, 9.0).forward, forward_about_y(90.0));  // after the last
  expect_vec3_near(sample_camera_animation(node, 1.5).position, {1.0f, 2.0f, 3.0f});    // the rest translation
  EXPECT_FLOAT_EQ(sample_camera_animation(node, 1.5).yfov, 0.5f);
}

TEST(CameraViews, StepRotationHoldsTheLastKeyUntilTheNext) {
  const SceneCameraNode node = rotating_node(true);
  expect_vec3_near(sample_camera_animation(node, 1.0).forward, forward_about_y(0.0));
  expect_vec3_near(sample_camera_animation(node, 1.999).forward, forward_about_y(0.0));
  expect_vec3_near(sample_camera_animation(node, 2.0).forward, forward_about_y(90.0));
}

TEST(CameraViews, SampleTimesCoverTheAnimationAtTheFrameRate) {
  const SceneCameraNode node = rotating_node(false);
  const std::vector<double> times = animation_sample_times(*node.animation, 4.0);
  ASSERT_EQ(times.size(), 5u);  // 1, 1.25, 1.5, 1.75, 2
  EXPECT_DOUBLE_EQ(times.front(), 1.0);
  EXPECT_DOUBLE_EQ(times.back(), 2.0);
  EXPECT_EQ(animation_sample_times(*node.animation, 2.5).size(), 3u);  // 1, 1.4, 1.8
}

ViewRequest camera_request(const char* camera, bool animation = false, double fps = 24.0) {
  ViewRequest request;
  request.camera = camera;
  request.animation = animation;
  request.fps = fps;
  return request;
}

TEST(CameraViews, SelectionBySourceAndItsErrors) {
  const Scene s = load_gltf(test_file("good/cornell-walk.gltf"));
  EXPECT_EQ(select_views(s, ViewRequest{}).size(), 1u);
  ViewRequest all;
  all.all_cameras = true;
  EXPECT_EQ(select_views(s, all).size(), 3u);
  expect_vec3_near(select_views(s, camera_request("left")).front().position, s.camera_nodes[1].view.position);
  // The glTF camera's name: its first node.
  expect_vec3_near(select_views(s, camera_request("Cornell camera (35 mm lens, 25 mm film)")).front().position,
                   s.camera_nodes[0].view.position);
  EXPECT_THROW(select_views(s, camera_request("3")), std::invalid_argument);
  EXPECT_THROW(select_views(s, camera_request("white")), std::invalid_argument);  // a mesh node
  EXPECT_THROW(select_views(s, camera_request("2", true, 0.0)), std::invalid_argument);
  EXPECT_EQ(select_views(s, camera_request("2", true, 10.0)).size(), 11u);
}

}  // namespace
}  // namespace bp
