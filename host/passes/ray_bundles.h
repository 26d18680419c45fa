// Driver of global ray-bundle iteration (kernels/bundle.cl, docs/design.md §4): one random direction per
// iteration, radiance of every patch moved one bounce along it through the software
// transillumination buffer, and the eye estimate of each iteration added to the image.
#pragma once
#include "device/device_scan.h"
#include "device/device_scene.h"
#include "device/program_cache.h"
#include "passes/pass.h"
#include "passes/bundle_directions.h"
#include "scene/bundle_geometry.h"

#include <cstdint>
#include <string>

namespace bp {

// Tiled fragment buffers are sized for every fragment slot when that costs at most this much: no
// iteration then waits for the host to read its fragment count (on small scenes the sync costs more
// than the memory). Larger scenes read the count back and grow the buffers when needed.
constexpr std::size_t kStaticTiledBytes = std::size_t(64) << 20;

// Touching surfaces (README, "Ray-bundle discretisation"): two consecutive fragments of a bin closer
// than this fraction of the scene's bounding diameter along omega exchange nothing, and a patch's
// incoming radiance is the mean over its other fragments. A patch partly covered by what rests on it
// (a box on a floor, the Cornell light 0.1 mm under its ceiling) then reflects what its visible part
// receives, instead of a mean that the covered part darkens and the eye's interpolation spreads.
constexpr float kContactDepthFraction = 1e-3f;

struct RayBundleSettings {
  std::uint32_t seed = 1;
  std::uint32_t bins = 0;             // R: bins per side of the transillumination buffer; 0 = default_bins
  std::uint32_t warmup = 0;           // iterations run before the first eye estimate is kept
  std::uint32_t jitter_refresh = 16;  // iterations between new jittered primary hits per pixel
  // The eye estimate of Lambert eye vertices (flat normal; not the paper's weights) gathered once per
  // block of iterations -- the iterations between new eye hits or flushes -- from per-patch sums
  // (docs/design.md §8; kernels/bundle.cl, eye_in_blocks): the same sums as every iteration's gather, in
  // another order, for a fraction of its cost. false: every pixel every iteration (tests compare).
  bool eye_blocks = true;
  bool glossy = true;  // some f depends on the directions: a Phong lobe or glTF's metallic-roughness BRDF
                      // (its eye vertices are gathered every iteration)
  bool gouraud = true;                // interpolate E_in across patches in the eye estimate
  std::uint32_t weight_mode = BP_WEIGHTS_NONE;
  float weight_ratio = 1.0f;          // N2 / N1
  std::uint32_t beta_heuristic = BP_BETA_CLAMPED;  // product weights' per-vertex beta (BP_BETA_*)
  float light_rate = 1.0f;            // probability that a patch traces its light sample in an iteration
  bool sun_own = false;               // --rb-sun own: that patch also samples each directional light
  bool keep_raw = false;              // also the unweighted image (rb_raw)
  bool light_sampling = false;        // per-patch light samples and per-fragment weighted direct light
                                      // (docs/design.md §3); product weights only, where the scene has lights
  bool eye_direct_shared = false;     // with light sampling: the eye vertex's direct light split with PT
                                      // (--eye-direct shared; a chain and a light-sample buffer more)
  std::string kernel_options;         // feature switches (device/kernel_features.h); empty: generic
  std::size_t static_tiled_bytes = kStaticTiledBytes;
  float contact_depth_fraction = kContactDepthFraction;  // 0: touching surfaces exchange radiance too
  DirectionSequence directions = DirectionSequence::independent;  // the iterations' directions (bundle_directions.h)
};

// Bins per side so that an element of average area covers `bins_per_element` bins on average
// (its mean projected area is half its area, over directions uniform on the sphere).
inline constexpr double kDefaultBinsPerElement = 4.0;
std::uint32_t default_bins(const BundleSize& size, double bins_per_element = kDefaultBinsPerElement);

// The rate at which a patch traces its light sample in an iteration (light sampling, docs/design.md §3):
// about as many shadow rays per iteration as the image has pixels, and every patch on scenes with
// fewer patches than pixels. A shadow ray per patch made an iteration on a 122 000-patch scene four
// to five times dearer than without light sampling.
float default_light_rate(std::size_t patches, std::size_t pixels);

// Expected fragments per iteration: sum of projected areas over the bin area, exact in expectation.
double expected_fragments(const BundleSize& size, std::uint32_t bins);

// Radiance chains the pass keeps per patch and fragment: the weighted one, the direct one with light
// sampling, and the unweighted one when --weights product must also give rb_raw (bundle_types.h).
std::uint32_t bundle_chains(const RayBundleSettings& settings);

// Device memory the pass will allocate (host memory alike), for the check before allocating;
// shading_normals: the scene has NORMAL corners (a shading normal per eye hit); textures: it has
// textures (the texel material per eye hit).
std::size_t estimate_bundle_memory(const BundleSize& size, std::uint32_t bins, std::size_t pixels,
                                   std::uint32_t chains = 1, bool shading_normals = false, bool textures = false);

// Throws std::invalid_argument naming --bins / --patch-size when the estimate does not fit the device.
void check_bundle_memory(const DeviceInfo& device, const BundleSize& size, std::uint32_t bins, std::size_t pixels,
                         std::uint32_t chains = 1, bool shading_normals = false, bool textures = false);

// One view the pass gathers an eye estimate for: its camera and the accumulator the estimates go to
// (sized like the camera's image; raw too if the pass keeps raw).
struct RayBundleView {
  CameraParams camera{};
  Accumulator* accum = nullptr;
};

class RayBundlePass : public ProgressivePass {
 public:
  // Adds its eye estimates into `accum`.
  RayBundlePass(const DeviceContext& device, const DeviceScene& scene, const BundleGeometry& geometry,
                const CameraParams& camera, const RayBundleSettings& settings, Accumulator& accum);
  // Several views of one chain (walkthroughs, docs/design.md §8): the patch state is view-independent, so
  // each iteration runs once and each view adds its own eye gather (its own eye hits and sums). All
  // views have the same image size. View k's image is the one-view pass's with view k's camera.
  RayBundlePass(const DeviceContext& device, const DeviceScene& scene, const BundleGeometry& geometry,
                const std::vector<RayBundleView>& views, const RayBundleSettings& settings);

  // Iterations [first, first + count) (after the warm-up, run on the first call). Any count: the
  // device's float sums are flushed to the accumulator's doubles every max_batch() iterations.
  BatchCounts run(std::uint64_t first, std::uint32_t count) override;
  std::uint32_t max_batch() const override { return 64; }
  const Launcher& launcher() const override { return launcher_; }
  const BuiltProgram& program() const override { return program_; }
  std::uint32_t bins() const { return bins_; }
  // N2 / N1 of the weights from the next iteration on (--ratio auto sets it once, after its probe).
  void set_weight_ratio(float n2_over_n1) { settings_.weight_ratio = n2_over_n1; }
  std::uint32_t pixel_width() const { return views_.front().camera.width; }
  std::uint32_t pixel_height() const { return views_.front().camera.height; }
  std::size_t view_count() const { return views_.size(); }

  // One iteration without an eye estimate (the warm-up, and tests that read patch radiance).
  void iterate(std::uint64_t iteration);
  // E_in = L_in cos(theta_in) of every patch after the last iteration (RGBA; `chains` per patch).
  std::vector<cl_float4> read_patch_irradiance();
  // L_out of every patch in the last iteration, and the bins each element covered (for tests).
  std::vector<cl_float4> read_patch_outgoing();
  std::vector<cl_uint> read_fragment_counts();
  // What a checkpoint must keep to continue exactly: the patches' incoming radiance after the last
  // iteration, and how far the warm-up and the jittered eye hits have got.
  struct State {
    std::vector<cl_float4> e_in;
    std::uint64_t eye_rounds = 0;
    bool warmed_up = false;
  };
  State save_state();
  void load_state(const State& state);  // throws std::runtime_error if it does not fit this pass

  // This iteration's direction and grid (a pure function of seed and iteration).
  BundleIteration iteration_params(std::uint64_t iteration) const;

 private:
  void ensure_fragment_capacity(std::size_t fragments);
  // Each view's jittered primary hits of this jitter period.
  void trace_eye_hits(std::uint64_t jitter_index);
  // Adds the device's float sums of eye estimates into the accumulator (double) and clears them;
  // the fragment count since the last flush too. Gathers the open block first.
  void flush_pixel_sums(BatchCounts& counts);
  // The eye estimates of the block's iterations at the pixels gathered in blocks, into their sums.
  void gather_eye_block();

  // A view's eye gather: its primary hits (with their shading normals and texels: scenes with NORMAL,
  // with textures; else one entry each) and the device's float sums of its eye estimates.
  struct EyeView {
    CameraParams camera{};
    Accumulator* accum = nullptr;
    cl::Buffer hits, normals, texels, pixel_sum;
  };

  const DeviceContext& device_;
  const DeviceScene& scene_;
  RayBundleSettings settings_;
  std::uint32_t chains_, eye_outputs_;
  std::vector<EyeView> views_;
  std::uint32_t bins_;
  std::size_t element_count_, patch_count_, pixel_count_, tile_count_;
  glm::vec3 centre_;
  float radius_;
  BuiltProgram program_;
  Launcher launcher_;
  DeviceScan scan_;
  cl::Kernel outgoing_, emit_, tile_scatter_, tile_resolve_, gather_, eye_hits_, vertex_, eye_, eye_patches_,
      eye_block_gather_;
  bool eye_blocks_ = false;          // some pixels are gathered in blocks (settings, not the paper's weights)
  bool eye_every_iteration_ = true;  // some pixels may be gathered every iteration (rb_eye runs)
  std::uint32_t block_iterations_ = 0;  // iterations in the open block
  cl::Buffer eye_block_;             // per patch, corner and eye output: the open block's sums
  cl::Buffer elements_, patch_element_, e_in_, l_out_;
  cl::Buffer eye_light_;  // per patch: its light sample weighted for the eye vertex, and its direction
  // Fragments in per-element slots (slot_start: raster_fragment_bound of them per element).
  cl::Buffer slot_start_, fragment_counts_, fragment_key_, fragment_depth_, tiled_at_, fragment_total_;
  std::size_t slot_count_ = 0;
  bool static_capacity_ = false;  // the tiled buffers hold every slot (else: read back and grow)
  cl::Buffer patch_vertices_, vertex_patch_start_, vertex_patches_, e_vertex_;
  std::size_t vertex_count_;
  cl::Buffer tile_counts_, tile_start_;
  cl::Buffer received_minus_, received_plus_;
  cl::Buffer tiled_local_, tiled_depth_, tiled_element_, tile_order_;
  std::size_t fragment_capacity_ = 0;
  bool warmed_up_ = false;
  std::uint64_t eye_rounds_ = 0;  // eye estimates so far (drives the jitter refresh)
  std::vector<cl_float4> host_pixel_sum_;
};

}  // namespace bp
