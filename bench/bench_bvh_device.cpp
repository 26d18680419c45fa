// BVH ray throughput of the OpenCL kernel (kernels/bench/trace_rays.cl, the same traversal the path
// tracer runs) on the fixed ray set of bench/ray_set.h, for ~1k / 100k / 1M triangles of two
// procedural scenes. With Embree 3 present (libembree-dev), the same rays go through Embree with as
// many threads as the machine has, and the ratio is printed. Prints a Markdown table.
// Usage: build/bench/bench_bvh_device [--device SPEC] [--repeat N] [--max-triangles N]
// (--max-triangles skips the larger scenes; bench/kernels.sh --quick uses it.)
#include "ray_set.h"

#include "device/device_context.h"
#include "device/launcher.h"
#include "device/program_cache.h"
#include "scene/bvh.h"
#include "scene/procedural.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#ifdef BP_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace {

using clock_type = std::chrono::steady_clock;

double device_mrays(const bp::DeviceContext& device, const bp::FlatBvh& bvh, const bp::bench::RaySet& rays,
                    int repeat, std::vector<float>& t_out) {
  bp::BuiltProgram program = bp::build_program(device, "bench/trace_rays.cl");
  cl::Kernel kernel(program.program, "trace_closest");
  std::vector<cl_float4> packed(rays.origin.size() * 2);
  for (std::size_t i = 0; i < rays.origin.size(); ++i) {
    packed[2 * i] = cl_float4{{rays.origin[i].x, rays.origin[i].y, rays.origin[i].z, 0}};
    packed[2 * i + 1] = cl_float4{{rays.dir[i].x, rays.dir[i].y, rays.dir[i].z, 0}};
  }
  cl::Buffer nodes = bp::upload_buffer(device, "bvh nodes", bvh.nodes);
  cl::Buffer tris = bp::upload_buffer(device, "bvh triangles", bvh.triangles);
  cl::Buffer ray_buffer = bp::upload_buffer(device, "rays", packed);
  cl::Buffer hits = bp::make_buffer(device, "hits", CL_MEM_WRITE_ONLY, rays.origin.size() * sizeof(float));
  const cl_uint count = cl_uint(rays.origin.size());
  bp::set_args(kernel, nodes, tris, ray_buffer, count, hits);
  bp::Launcher launcher(device);
  double best = 1e30;
  for (int r = 0; r <= repeat; ++r) {  // the first launch also compiles for the work-group size
    auto start = clock_type::now();
    launcher.launch("trace_closest", kernel, count, 64);
    launcher.finish();
    double s = std::chrono::duration<double>(clock_type::now() - start).count();
    if (r > 0) best = std::min(best, s);
  }
  t_out.resize(count);
  device.queue.enqueueReadBuffer(hits, CL_TRUE, 0, count * sizeof(float), t_out.data());
  return double(count) / best * 1e-6;
}

#ifdef BP_HAVE_EMBREE
double embree_mrays(const bp::Scene& scene, const bp::bench::RaySet& rays, int repeat, std::vector<float>& t_out) {
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene rtc_scene = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const std::size_t n = scene.triangles.size();
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) vertices[(3 * t + k) * 3 + c] = scene.triangles[t].p[k][c];
      indices[3 * t + k] = unsigned(3 * t + k);
    }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(rtc_scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(rtc_scene);
  const std::size_t count = rays.origin.size();
  t_out.assign(count, -1.0f);
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  double best = 1e30;
  for (int r = 0; r < repeat; ++r) {
    auto start = clock_type::now();
    std::vector<std::thread> pool;
    for (unsigned w = 0; w < threads; ++w)
      pool.emplace_back([&, w] {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (std::size_t i = w; i < count; i += threads) {
          RTCRayHit rh{};
          rh.ray.org_x = rays.origin[i].x; rh.ray.org_y = rays.origin[i].y; rh.ray.org_z = rays.origin[i].z;
          rh.ray.dir_x = rays.dir[i].x; rh.ray.dir_y = rays.dir[i].y; rh.ray.dir_z = rays.dir[i].z;
          rh.ray.tnear = 0.0f;
          rh.ray.tfar = 1e30f;
          rh.ray.mask = 0xffffffffu;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(rtc_scene, &context, &rh);
          if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) t_out[i] = rh.ray.tfar;
        }
      });
    for (auto& t : pool) t.join();
    best = std::min(best, std::chrono::duration<double>(clock_type::now() - start).count());
  }
  rtcReleaseScene(rtc_scene);
  rtcReleaseDevice(device);
  return double(count) / best * 1e-6;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  std::string device_spec;
  int repeat = 5;
  std::size_t max_triangles = ~std::size_t(0);
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--device" && i + 1 < argc) device_spec = argv[++i];
    else if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::stoi(argv[++i]));
    else if (a == "--max-triangles" && i + 1 < argc) max_triangles = std::stoull(argv[++i]);
    else {
      std::fprintf(stderr, "usage: bench_bvh_device [--device SPEC] [--repeat N] [--max-triangles N]\n");
      return 2;
    }
  }
  bp::DeviceContext device(bp::select_device(device_spec));
  std::printf("device: %s\n\n", device.description().c_str());
#ifdef BP_HAVE_EMBREE
  std::printf("| scene | triangles | rays | bundlepath Mrays/s | Embree 3 Mrays/s (%u threads) | ratio | rays that disagree |\n",
              std::max(1u, std::thread::hardware_concurrency()));
  std::printf("|---|---|---|---|---|---|---|\n");
#else
  std::printf("| scene | triangles | rays | bundlepath Mrays/s |\n|---|---|---|---|\n");
#endif
  for (const char* kind : {"rooms", "random"})
    for (std::size_t n : {1000u, 100000u, 1000000u}) {
      if (n > max_triangles) continue;
      bp::Scene scene = std::string(kind) == "rooms" ? bp::make_rooms_scene(n, 1) : bp::make_random_triangles_scene(n, 1);
      bp::FlatBvh bvh = bp::build_bvh(scene.triangles);
      bp::bench::RaySet rays = bp::bench::make_rays(scene, bvh);
      std::vector<float> ours;
      double mrays = device_mrays(device, bvh, rays, repeat, ours);
#ifdef BP_HAVE_EMBREE
      std::vector<float> reference;
      double embree = embree_mrays(scene, rays, repeat, reference);
      std::size_t disagree = 0;
      for (std::size_t i = 0; i < ours.size(); ++i)
        if ((ours[i] < 0) != (reference[i] < 0) ||
            (ours[i] >= 0 && std::fabs(ours[i] - reference[i]) > 1e-3f * std::max(1.0f, reference[i])))
          ++disagree;
      std::printf("| %s | %zu | %zu | %.2f | %.2f | %.2f | %zu |\n", kind, scene.triangles.size(), rays.origin.size(),
                  mrays, embree, mrays / embree, disagree);
#else
      std::printf("| %s | %zu | %zu | %.2f |\n", kind, scene.triangles.size(), rays.origin.size(), mrays);
#endif
      std::fflush(stdout);
    }
  return 0;
}
