#include "passes/ray_bundles.h"

#include "passes/bundle_directions.h"

#include "kernels/shared/bundle_raster.h"
#include "kernels/shared/frame.h"
#include "kernels/shared/rng.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bp {
namespace {

constexpr std::uint32_t kDirectionStream = 0x0b0d1e5u;  // RNG stream of the iteration directions
constexpr std::uint32_t kLightSeedSalt = 0x119b7a11u;   // the per-patch light samples' seed: seed ^ salt
// Per element slot (raster_fragment_bound of them per element): key, depth, where it was tiled.
constexpr std::size_t kSlotBytes = 3 * 4;
// Per tiled fragment: local bin, depth, element, tile order; then 2 received radiances per chain.
std::size_t tiled_fragment_bytes(std::uint32_t chains) { return 4 * 4 + 2 * sizeof(cl_float4) * chains; }

cl_uint as_uint(std::size_t v) { return cl_uint(v); }

}  // namespace

std::uint32_t default_bins(const BundleSize& size, double bins_per_element) {
  if (size.elements == 0) return 16;
  double mean_projected = 0.5 * size.element_area / double(size.elements);
  double bin_size = std::sqrt(mean_projected / bins_per_element);
  return std::uint32_t(std::clamp(std::ceil(2.0 * size.radius / bin_size), 16.0, 4096.0));
}

float default_light_rate(std::size_t patches, std::size_t pixels) {
  return patches > pixels ? float(double(pixels) / double(patches)) : 1.0f;
}

double expected_fragments(const BundleSize& size, std::uint32_t bins) {
  double bin_size = 2.0 * size.radius / bins;
  return 0.5 * size.element_area / (bin_size * bin_size);
}

namespace {
// Fragments per iteration that a read-back capacity starts with (it grows when an iteration needs more).
std::size_t dynamic_capacity(const BundleSize& size, std::uint32_t bins) {
  return std::size_t(1.5 * expected_fragments(size, bins)) + size.elements + 1024;
}
// Sum of raster_fragment_bound over the elements, from above (the bound's ceil adds at most 1 each).
std::size_t slot_estimate(const BundleSize& size, std::uint32_t bins) {
  const double bin_size = 2.0 * size.radius / bins;
  return std::size_t(size.element_area / (bin_size * bin_size) * 1.0001 + size.element_perimeter / bin_size * 0.501) +
         4 * size.elements;
}
bool static_tiled_capacity(std::size_t slots, std::uint32_t chains, std::size_t budget = kStaticTiledBytes) {
  return slots * tiled_fragment_bytes(chains) <= budget;
}
std::size_t tiled_capacity(const BundleSize& size, std::uint32_t bins, std::uint32_t chains) {
  const std::size_t slots = slot_estimate(size, bins);
  return static_tiled_capacity(slots, chains) ? slots : dynamic_capacity(size, bins);
}
}  // namespace

namespace {
bool samples_lights(const RayBundleSettings& settings) {
  return settings.weight_mode == BP_WEIGHTS_PRODUCT && settings.light_sampling;
}
bool shares_eye_direct(const RayBundleSettings& settings) {
  return samples_lights(settings) && settings.eye_direct_shared;
}
}  // namespace

std::uint32_t bundle_chains(const RayBundleSettings& settings) {
  const bool product = settings.weight_mode == BP_WEIGHTS_PRODUCT;
  return 1u + (samples_lights(settings) ? 1u : 0u) + (shares_eye_direct(settings) ? 1u : 0u) +
         (product && settings.keep_raw ? 1u : 0u);
}

std::size_t estimate_bundle_memory(const BundleSize& size, std::uint32_t bins, std::size_t pixels, std::uint32_t chains,
                                   bool shading_normals, bool textures) {
  std::size_t tiles_per_side = bundle_tiles_per_side(bins + 1), tiles = tiles_per_side * tiles_per_side + 1;
  return slot_estimate(size, bins) * kSlotBytes + tiled_capacity(size, bins, chains) * tiled_fragment_bytes(chains) +
         tiles * 2 * sizeof(cl_uint) + size.patches * (4 * sizeof(cl_uint) + 2 * chains * sizeof(cl_float4)) +
         size.patches * 5 * sizeof(cl_float4) +  // the eye vertex's light samples and their Gouraud vertices (at most)
         size.elements * (sizeof(BundleElement) + 2 * sizeof(cl_uint)) +
         size.patches * 3 * (sizeof(cl_uint) + chains * sizeof(cl_float4)) +  // Gouraud vertices (at most 3 per patch)
         size.patches * 3 * 2 * sizeof(cl_float4) +  // the eye block's sums per patch corner (at most 2 outputs)
         pixels * (sizeof(EyeHit) + 2 * sizeof(cl_float4) + (shading_normals ? sizeof(cl_float4) : 0) +
                   (textures ? 3 * sizeof(cl_float4) : 0));
}

void check_bundle_memory(const DeviceInfo& device, const BundleSize& size, std::uint32_t bins, std::size_t pixels,
                         std::uint32_t chains, bool shading_normals, bool textures) {
  const std::size_t need = estimate_bundle_memory(size, bins, pixels, chains, shading_normals, textures);
  const std::size_t largest = std::max(tiled_capacity(size, bins, chains) * chains * sizeof(cl_float4),
                                       slot_estimate(size, bins) * sizeof(cl_uint));
  // Leave a quarter of the device for the scene, the path tracer and the driver.
  if (need > device.global_memory_bytes / 4 * 3 || largest > device.max_alloc_bytes)
    throw std::invalid_argument(
        "the ray-bundle pass needs about " + std::to_string(need >> 20) + " MiB (" +
        std::to_string(std::size_t(expected_fragments(size, bins))) + " fragments per iteration at --bins " +
        std::to_string(bins) + ", " + std::to_string(size.patches) + " patches), more than " + device.device_name +
        " offers (" + std::to_string(device.global_memory_bytes >> 20) + " MiB, at most " +
        std::to_string(device.max_alloc_bytes >> 20) + " MiB per buffer): lower --bins or raise --patch-size");
}

RayBundlePass::RayBundlePass(const DeviceContext& device, const DeviceScene& scene, const BundleGeometry& geometry,
                             const CameraParams& camera, const RayBundleSettings& settings, Accumulator& accum)
    : RayBundlePass(device, scene, geometry, {RayBundleView{camera, &accum}}, settings) {}

RayBundlePass::RayBundlePass(const DeviceContext& device, const DeviceScene& scene, const BundleGeometry& geometry,
                             const std::vector<RayBundleView>& views, const RayBundleSettings& settings)
    : device_(device),
      scene_(scene),
      settings_(settings),
      chains_(bundle_chains(settings)),
      eye_outputs_(settings.keep_raw ? 2u : 1u),
      bins_(settings.bins ? settings.bins : default_bins(bundle_size(geometry))),
      element_count_(geometry.elements.size()),
      patch_count_(geometry.patch_element.size()),
      pixel_count_(std::size_t(views.front().camera.width) * views.front().camera.height),
      tile_count_(std::size_t(bundle_tiles_per_side(bins_ + 1)) * bundle_tiles_per_side(bins_ + 1)),
      centre_(geometry.centre),
      radius_(geometry.radius),
      program_(build_program(device, "bundle.cl", settings.kernel_options)),
      launcher_(device),
      scan_(device, program_.program) {
  const cl::Program& p = program_.program;
  outgoing_ = cl::Kernel(p, "rb_outgoing");
  emit_ = cl::Kernel(p, "rb_emit");
  tile_scatter_ = cl::Kernel(p, "rb_tile_scatter");
  tile_resolve_ = cl::Kernel(p, "rb_tile_resolve");
  gather_ = cl::Kernel(p, "rb_gather");
  eye_hits_ = cl::Kernel(p, "rb_eye_hits");
  vertex_ = cl::Kernel(p, "rb_vertex");
  eye_ = cl::Kernel(p, "rb_eye");
  eye_patches_ = cl::Kernel(p, "rb_eye_patches");
  eye_block_gather_ = cl::Kernel(p, "rb_eye_block");
  eye_blocks_ = settings.eye_blocks && settings.weight_mode != BP_WEIGHTS_PAPER;
  eye_every_iteration_ = !eye_blocks_ || settings.glossy || scene.has_shading_normals;

  elements_ = upload_buffer(device, "bundle elements", geometry.elements);
  patch_element_ = upload_buffer(device, "patch elements", geometry.patch_element);
  vertex_count_ = geometry.vertex_patch_start.empty() ? 0 : geometry.vertex_patch_start.size() - 1;
  patch_vertices_ = upload_buffer(device, "patch vertices", geometry.patch_vertices);
  vertex_patch_start_ = upload_buffer(device, "vertex patch offsets", geometry.vertex_patch_start);
  vertex_patches_ = upload_buffer(device, "vertex patches", geometry.vertex_patches);
  // Per vertex: every chain, and with --eye-direct shared the eye's light samples (rb_vertex).
  const std::size_t vertex_slots = chains_ + (shares_eye_direct(settings) ? 1 : 0);
  e_vertex_ = make_buffer(device, "vertex irradiance", CL_MEM_READ_WRITE, vertex_count_ * vertex_slots * sizeof(cl_float4));
  e_in_ = make_buffer(device, "patch irradiance", CL_MEM_READ_WRITE, patch_count_ * chains_ * sizeof(cl_float4));
  l_out_ =
      make_buffer(device, "patch outgoing radiance", CL_MEM_READ_WRITE, patch_count_ * chains_ * sizeof(cl_float4));
  eye_light_ = make_buffer(device, "eye-vertex light samples", CL_MEM_READ_WRITE,
                           (shares_eye_direct(settings) ? patch_count_ : 1) * 2 * sizeof(cl_float4));
  // Each element rasterizes into slots of its own, as many as it can ever cover.
  const float bin_size = 2.0f * radius_ / float(bins_);
  std::vector<cl_uint> slot_start(element_count_ + 1, 0u);
  for (std::size_t e = 0; e < element_count_; ++e) {
    const BundleElement& el = geometry.elements[e];
    const glm::vec3 e1(el.e1[0], el.e1[1], el.e1[2]), e2(el.e2[0], el.e2[1], el.e2[2]);
    const float perimeter = glm::length(e1) + glm::length(e2) + glm::length(e2 - e1);
    const std::size_t next = std::size_t(slot_start[e]) + raster_fragment_bound(el.area, perimeter, bin_size);
    if (next > 0xffffffffu) throw std::invalid_argument("the ray-bundle pass would need more than 2^32 fragment "
                                                        "slots: lower --bins or raise --patch-size");
    slot_start[e + 1] = cl_uint(next);
  }
  slot_count_ = slot_start.back();
  static_capacity_ = static_tiled_capacity(slot_count_, chains_, settings.static_tiled_bytes);
  slot_start_ = upload_buffer(device, "fragment slot starts", slot_start);
  fragment_counts_ = make_buffer(device, "fragment counts", CL_MEM_READ_WRITE, element_count_ * sizeof(cl_uint));
  fragment_key_ = make_buffer(device, "fragment keys", CL_MEM_READ_WRITE, slot_count_ * sizeof(cl_uint));
  fragment_depth_ = make_buffer(device, "fragment depths", CL_MEM_READ_WRITE, slot_count_ * sizeof(cl_float));
  tiled_at_ = make_buffer(device, "fragment places in their tiles", CL_MEM_READ_WRITE, slot_count_ * sizeof(cl_uint));
  tile_counts_ = make_buffer(device, "tile counts", CL_MEM_READ_WRITE, tile_count_ * sizeof(cl_uint));
  tile_start_ = make_buffer(device, "tile starts", CL_MEM_READ_WRITE, (tile_count_ + 1) * sizeof(cl_uint));
  fragment_total_ = make_buffer(device, "fragment total", CL_MEM_READ_WRITE, sizeof(cl_ulong));
  device.queue.enqueueFillBuffer(tile_counts_, cl_uint(0), 0, tile_count_ * sizeof(cl_uint));
  device.queue.enqueueFillBuffer(fragment_total_, cl_ulong(0), 0, sizeof(cl_ulong));
  for (const RayBundleView& v : views) {
    if (std::size_t(v.camera.width) * v.camera.height != pixel_count_)
      throw std::invalid_argument("the ray-bundle pass's views must have one image size");
    EyeView view;
    view.camera = v.camera;
    view.accum = v.accum;
    view.hits = make_buffer(device, "eye hits", CL_MEM_READ_WRITE, pixel_count_ * sizeof(EyeHit));
    view.normals = make_buffer(device, "eye hit shading normals", CL_MEM_READ_WRITE,
                               (scene.has_shading_normals ? pixel_count_ : 1) * sizeof(cl_float4));
    view.texels = make_buffer(device, "eye hit texels", CL_MEM_READ_WRITE,
                              (scene.uv_slots > 0 ? BP_EYE_TEXELS * pixel_count_ : 1) * sizeof(cl_float4));
    view.pixel_sum =
        make_buffer(device, "eye estimate sums", CL_MEM_READ_WRITE, pixel_count_ * eye_outputs_ * sizeof(cl_float4));
    device.queue.enqueueFillBuffer(view.pixel_sum, cl_float4{{0, 0, 0, 0}}, 0,
                                   pixel_count_ * eye_outputs_ * sizeof(cl_float4));
    views_.push_back(view);
  }
  device.queue.enqueueFillBuffer(e_in_, cl_float4{{0, 0, 0, 0}}, 0, patch_count_ * chains_ * sizeof(cl_float4));
  const std::size_t block_bytes = (eye_blocks_ ? patch_count_ * 3 * eye_outputs_ : 1) * sizeof(cl_float4);
  eye_block_ = make_buffer(device, "eye block sums", CL_MEM_READ_WRITE, block_bytes);
  device.queue.enqueueFillBuffer(eye_block_, cl_float4{{0, 0, 0, 0}}, 0, block_bytes);
  ensure_fragment_capacity(static_capacity_ ? slot_count_ : dynamic_capacity(bundle_size(geometry), bins_));
  host_pixel_sum_.resize(pixel_count_ * eye_outputs_);
}

void RayBundlePass::ensure_fragment_capacity(std::size_t fragments) {
  if (fragments <= fragment_capacity_) return;
  std::size_t n = std::max(fragments, fragment_capacity_ + fragment_capacity_ / 4);
  tiled_local_ = make_buffer(device_, "tiled fragment bins", CL_MEM_READ_WRITE, n * sizeof(cl_uint));
  tiled_depth_ = make_buffer(device_, "tiled fragment depths", CL_MEM_READ_WRITE, n * sizeof(cl_float));
  tiled_element_ = make_buffer(device_, "tiled fragment elements", CL_MEM_READ_WRITE, n * sizeof(cl_uint));
  tile_order_ = make_buffer(device_, "tile order", CL_MEM_READ_WRITE, n * sizeof(cl_uint));
  received_minus_ =
      make_buffer(device_, "received radiance (-omega side)", CL_MEM_READ_WRITE, n * chains_ * sizeof(cl_float4));
  received_plus_ =
      make_buffer(device_, "received radiance (+omega side)", CL_MEM_READ_WRITE, n * chains_ * sizeof(cl_float4));
  fragment_capacity_ = n;
}

BundleIteration RayBundlePass::iteration_params(std::uint64_t iteration) const {
  auto direction = [&](std::uint64_t i, float* rotation, float* ou, float* ov) {
    Rng rng = rng_init(settings_.seed, kDirectionStream, std::uint32_t(i));
    UnitSquarePoint jitter;
    jitter.u1 = rng_uniform(&rng);
    jitter.u2 = rng_uniform(&rng);
    const UnitSquarePoint p = bundle_direction_point(settings_.directions, settings_.seed, i, settings_.warmup, jitter);
    const float u1 = p.u1, u2 = p.u2;
    if (rotation) *rotation = BP_TWO_PI * rng_uniform(&rng);
    if (ou) *ou = rng_uniform(&rng);
    if (ov) *ov = rng_uniform(&rng);
    float z = 1.0f - 2.0f * u1, s = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = BP_TWO_PI * u2;
    return make_float3(s * std::cos(phi), s * std::sin(phi), z);  // uniform on the sphere
  };
  BundleIteration it{};
  float rotation = 0, ou = 0, ov = 0;
  float3 omega = direction(iteration, &rotation, &ou, &ov);
  float3 prev = iteration > 0 ? direction(iteration - 1, nullptr, nullptr, nullptr) : omega;
  float3 next = direction(iteration + 1, nullptr, nullptr, nullptr);  // drawn one ahead (docs/design.md §3)
  Frame f = frame_from_normal(omega);
  float3 u = f.t * std::cos(rotation) + f.b * std::sin(rotation);
  float3 v = cross(omega, u);
  const float3 vectors[5] = {omega, u, v, prev, next};
  float* targets[5] = {it.omega, it.axis_u, it.axis_v, it.omega_prev, it.omega_next};
  for (int k = 0; k < 5; ++k) {
    targets[k][0] = vectors[k].x;
    targets[k][1] = vectors[k].y;
    targets[k][2] = vectors[k].z;
  }
  for (int c = 0; c < 3; ++c) it.centre[c] = centre_[c];
  it.bin_size = 2.0f * radius_ / float(bins_);
  it.offset_u = ou;
  it.offset_v = ov;
  it.bins_per_side = bins_ + 1;
  it.weight_mode = settings_.weight_mode;
  it.chains = chains_;
  it.weight_ratio = settings_.weight_ratio;
  it.beta_heuristic = settings_.beta_heuristic;
  it.light_rate = settings_.light_rate;
  it.sun_own_samples = settings_.sun_own ? 1u : 0u;
  it.eye_outputs = eye_outputs_;
  it.light_count = samples_lights(settings_) ? scene_.light_count : 0u;
  it.direct_chain = samples_lights(settings_) ? 1u : 0u;
  it.eye_direct_chain = shares_eye_direct(settings_) ? 2u : 0u;
  it.contact_depth = settings_.contact_depth_fraction * 2.0f * radius_;
  it.shading_normals = scene_.has_shading_normals;
  it.environment_width = scene_.environment_width;
  it.environment_height = scene_.environment_height;
  it.environment_light = samples_lights(settings_) ? scene_.environment_light : BP_NO_LIGHT;
  return it;
}

void RayBundlePass::iterate(std::uint64_t iteration) {
  const BundleIteration it = iteration_params(iteration);
  const cl_uint patches = as_uint(patch_count_), elements = as_uint(element_count_);
  set_args(outgoing_, elements_, patch_element_, scene_.materials, e_in_, it, patches, l_out_, scene_.nodes,
           scene_.triangles, scene_.lights, scene_.light_cdf, cl_uint(settings_.seed ^ kLightSeedSalt),
           cl_uint(iteration), scene_.ray_epsilon, eye_light_, scene_.light_tree, scene_.light_receivers,
           cl_uint(scene_.light_selection), scene_.patch_materials, cl_uint(scene_.uv_slots), scene_.texture_views,
           scene_.texels, scene_.material_textures, scene_.texcoords, scene_.shading, cl_uint(scene_.alpha_masks),
           scene_.environment);
  launcher_.launch("rb_outgoing", outgoing_, patch_count_, 64);

  set_args(emit_, elements_, it, elements, slot_start_, fragment_counts_, fragment_key_, fragment_depth_, tile_counts_,
           cl_uint(scene_.alpha_masks), scene_.element_triangle, scene_.shading, scene_.texture_views, scene_.texels,
           scene_.material_textures, scene_.texcoords, cl_uint(scene_.uv_slots));
  launcher_.launch("rb_emit", emit_, element_count_, 64);
  scan_.exclusive(launcher_, tile_counts_, tile_count_, tile_start_);
  if (!static_capacity_) {  // the tiled buffers hold what this iteration needs, not every slot: check
    cl_uint fragments = 0;
    device_.queue.enqueueReadBuffer(tile_start_, CL_TRUE, tile_count_ * sizeof(cl_uint), sizeof(cl_uint), &fragments);
    ensure_fragment_capacity(fragments);
  }
  set_args(tile_scatter_, slot_start_, fragment_counts_, fragment_key_, fragment_depth_, elements, tile_start_,
           tile_counts_, tiled_at_, tiled_local_, tiled_depth_, tiled_element_);
  launcher_.launch("rb_tile_scatter", tile_scatter_, element_count_, 64);
  set_args(tile_resolve_, elements_, scene_.materials, tile_start_, tiled_local_, tiled_depth_, tiled_element_,
           tile_order_, l_out_, it, as_uint(tile_count_), received_minus_, received_plus_, fragment_total_,
           scene_.lights, scene_.light_cdf, scene_.light_tree, scene_.light_receivers, cl_uint(scene_.light_selection),
           scene_.patch_materials, cl_uint(scene_.uv_slots), scene_.environment);
  launcher_.launch("rb_tile_resolve", tile_resolve_, tile_count_, 8);

  set_args(gather_, elements_, slot_start_, fragment_counts_, tiled_at_, received_minus_, received_plus_, it, elements,
           e_in_, cl_uint(scene_.alpha_masks), scene_.element_coverage);
  launcher_.launch("rb_gather", gather_, element_count_, 64);
}

BatchCounts RayBundlePass::run(std::uint64_t first, std::uint32_t count) {
  BatchCounts counts;
  if (!warmed_up_) {
    for (std::uint32_t w = 0; w < settings_.warmup; ++w) iterate(w);
    warmed_up_ = true;
  }
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint64_t iteration = settings_.warmup + first + k;
    iterate(iteration);
    if (eye_rounds_ % settings_.jitter_refresh == 0) {
      gather_eye_block();  // with the hits it was summed for
      trace_eye_hits(eye_rounds_ / settings_.jitter_refresh);
      counts.rays += pixel_count_ * views_.size();
    }
    ++eye_rounds_;
    const BundleIteration it = iteration_params(iteration);
    if (settings_.gouraud) {
      set_args(vertex_, vertex_patch_start_, vertex_patches_, elements_, patch_element_, e_in_, it,
               as_uint(vertex_count_), e_vertex_, eye_light_, cl_uint(scene_.alpha_masks), scene_.element_coverage);
      launcher_.launch("rb_vertex", vertex_, vertex_count_, 64);
    }
    if (eye_blocks_) {  // once for every view: the patches' share of the block's eye estimates
      set_args(eye_patches_, elements_, patch_element_, scene_.materials, scene_.patch_materials,
               cl_uint(scene_.uv_slots), e_in_, patch_vertices_, e_vertex_, cl_uint(settings_.gouraud ? 1 : 0), it,
               as_uint(patch_count_), eye_light_, eye_block_);
      launcher_.launch("rb_eye_patches", eye_patches_, patch_count_, 64);
      ++block_iterations_;
    }
    for (std::size_t v = 0; eye_every_iteration_ && v < views_.size(); ++v) {
      const EyeView& view = views_[v];
      set_args(eye_, view.hits, elements_, patch_element_, scene_.materials, e_in_, patch_vertices_, e_vertex_,
               cl_uint(settings_.gouraud ? 1 : 0), it, as_uint(pixel_count_), view.pixel_sum, eye_light_,
               view.normals, scene_.patch_materials, cl_uint(scene_.uv_slots), view.texels, scene_.environment,
               cl_uint(eye_blocks_ ? 1 : 0));
      launcher_.launch("rb_eye", eye_, pixel_count_, 64);
    }
    // The device sums the eye estimates in float: move them to the host's double sums after every
    // max_batch() iterations (on multiples of it, wherever a batch starts) and at the batch's end, so
    // no float sum ever holds more than max_batch() terms -- also when a caller asks for 10^4
    // iterations at once (a round at --ratio 1e-4).
    if ((first + k + 1) % max_batch() == 0 || k + 1 == count) flush_pixel_sums(counts);
  }
  for (const EyeView& view : views_) view.accum->samples_per_pixel += count;
  return counts;
}

void RayBundlePass::gather_eye_block() {
  if (!eye_blocks_ || block_iterations_ == 0) return;
  // rb_eye_block reads only what every iteration shares (the weights' mode, the outputs, the
  // environment), not the direction: any iteration's parameters do.
  const BundleIteration it = iteration_params(0);
  for (const EyeView& view : views_) {
    set_args(eye_block_gather_, view.hits, elements_, patch_element_, scene_.materials, patch_vertices_,
             cl_uint(settings_.gouraud ? 1 : 0), it, as_uint(pixel_count_), view.pixel_sum, view.normals,
             scene_.patch_materials, cl_uint(scene_.uv_slots), view.texels, scene_.environment, eye_block_,
             float(block_iterations_));
    launcher_.launch("rb_eye_block", eye_block_gather_, pixel_count_, 64);
  }
  device_.queue.enqueueFillBuffer(eye_block_, cl_float4{{0, 0, 0, 0}}, 0,
                                  patch_count_ * 3 * eye_outputs_ * sizeof(cl_float4));
  block_iterations_ = 0;
}

void RayBundlePass::flush_pixel_sums(BatchCounts& counts) {
  gather_eye_block();
  launcher_.finish();
  const std::size_t bytes = host_pixel_sum_.size() * sizeof(cl_float4);
  cl_ulong fragments = 0;
  device_.queue.enqueueReadBuffer(fragment_total_, CL_TRUE, 0, sizeof(cl_ulong), &fragments);
  device_.queue.enqueueFillBuffer(fragment_total_, cl_ulong(0), 0, sizeof(cl_ulong));
  counts.fragments += fragments;
  for (const EyeView& view : views_) {
    Accumulator& accum = *view.accum;
    device_.queue.enqueueReadBuffer(view.pixel_sum, CL_TRUE, 0, bytes, host_pixel_sum_.data());
    device_.queue.enqueueFillBuffer(view.pixel_sum, cl_float4{{0, 0, 0, 0}}, 0, bytes);
    for (std::size_t i = 0; i < pixel_count_; ++i) {
      const cl_float4& w = host_pixel_sum_[i * eye_outputs_];
      const cl_float4& raw = host_pixel_sum_[i * eye_outputs_ + eye_outputs_ - 1];
      if (!std::isfinite(w.s[0] + w.s[1] + w.s[2] + raw.s[0] + raw.s[1] + raw.s[2])) {
        ++counts.nonfinite_samples;  // a pixel's sum since the last flush is dropped whole, and counted
        continue;
      }
      for (int c = 0; c < 3; ++c) accum.sum[i * 3 + c] += double(w.s[c]);
      if (accum.keeps_raw())
        for (int c = 0; c < 3; ++c) accum.raw_sum[i * 3 + c] += double(raw.s[c]);
    }
  }
}

namespace {
template <class T>
std::vector<T> read_all(const DeviceContext& device, Launcher& launcher, const cl::Buffer& buffer, std::size_t n) {
  launcher.finish();
  std::vector<T> out(n);
  if (n) device.queue.enqueueReadBuffer(buffer, CL_TRUE, 0, n * sizeof(T), out.data());
  return out;
}
}  // namespace

void RayBundlePass::trace_eye_hits(std::uint64_t jitter_index) {
  for (const EyeView& view : views_) {
    set_args(eye_hits_, scene_.nodes, scene_.triangles, scene_.shading, scene_.materials, view.camera,
             cl_uint(settings_.seed ^ 0x5eed0e7eu), cl_uint(jitter_index), view.hits, scene_.shading_normals,
             cl_uint(scene_.has_shading_normals), view.normals, cl_uint(scene_.uv_slots), scene_.texture_views,
             scene_.texels, scene_.material_textures, scene_.texcoords, view.texels, cl_uint(scene_.alpha_masks),
             scene_.ray_epsilon, scene_.tangents, scene_.cluster_fans);
    launcher_.launch("rb_eye_hits", eye_hits_, pixel_count_, 64);
  }
}

RayBundlePass::State RayBundlePass::save_state() {
  return State{read_patch_irradiance(), eye_rounds_, warmed_up_};
}

void RayBundlePass::load_state(const State& state) {
  if (state.e_in.size() != patch_count_ * chains_)
    throw std::runtime_error("the checkpoint holds " + std::to_string(state.e_in.size()) +
                             " patch radiances, this run has " + std::to_string(patch_count_ * chains_));
  device_.queue.enqueueWriteBuffer(e_in_, CL_TRUE, 0, state.e_in.size() * sizeof(cl_float4), state.e_in.data());
  eye_rounds_ = state.eye_rounds;
  warmed_up_ = state.warmed_up;
  if (eye_blocks_) {  // a state is saved after a flush: no open block
    device_.queue.enqueueFillBuffer(eye_block_, cl_float4{{0, 0, 0, 0}}, 0,
                                    patch_count_ * 3 * eye_outputs_ * sizeof(cl_float4));
    block_iterations_ = 0;
  }
  // The eye hits of the current jitter period, as the interrupted run had them.
  if (eye_rounds_ % settings_.jitter_refresh != 0) trace_eye_hits((eye_rounds_ - 1) / settings_.jitter_refresh);
}

std::vector<cl_float4> RayBundlePass::read_patch_irradiance() {
  return read_all<cl_float4>(device_, launcher_, e_in_, patch_count_ * chains_);
}

std::vector<cl_float4> RayBundlePass::read_patch_outgoing() {
  return read_all<cl_float4>(device_, launcher_, l_out_, patch_count_ * chains_);
}

std::vector<cl_uint> RayBundlePass::read_fragment_counts() {
  return read_all<cl_uint>(device_, launcher_, fragment_counts_, element_count_);
}

}  // namespace bp
