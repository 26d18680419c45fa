// The stages of a render: scene -> devices -> passes -> (probe) -> resume -> rounds -> outputs.
#include "render/render_job.h"

#include "image/stats_io.h"
#include "render/checkpoint_key.h"
#include "render/render_outputs.h"
#include "render/render_passes.h"
#include "render/render_state.h"
#include "render/render_stats.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

namespace bp {
namespace {

// The beauty's denoise against the prefilter of its albedo and normal, to keep it inside --time
// (prepare_features): one filter on three inputs against two filters on one each; an estimate, not
// timed apart. On the Lambert house at 640x360, --time 30 --denoise ended at 30.8 s of wall time,
// the rounds' last batch included (docs/results.md, "Denoised images").
constexpr double kDenoiseCostOverPrefilter = 0.75;

// PT's unweighted image u and its estimate of RB's share d = u − w, times the rounds.
RoundSums pt_raw_round_sums(const RenderState& s, const RenderView& view) {
  return RoundSums{&view.pt_accum.raw_sum, 1.0 / s.shape->pt_samples};
}
RoundSums pt_share_round_sums(const RenderState& s, const RenderView& view) {
  return RoundSums{&view.pt_accum.raw_sum, 1.0 / s.shape->pt_samples, &view.pt_accum.sum};
}

// --rb-level consistent: the image's error per pixel and channel (image/share_correction.h). The image
// is w + λ d + (1 − λ) r̃ at the pixel level (λ its weight of d): PT's part varies as
// Var(w) + λ² Var(d) + 2 λ Cov(w, d), the covariance from Var(u) = Var(w + d); RB's part's error,
// bias and noise, is what the correction left. Nothing before two batches of each.
void set_consistent_error(RenderState& s, RenderView& view, std::optional<std::uint64_t> rounds_done) {
  if (rounds_done) {
    view.pt_raw_batches->add(*rounds_done, pt_raw_round_sums(s, view));
    view.pt_share_batches->add(*rounds_done, pt_share_round_sums(s, view));
  }
  const ImageErrorEstimate& e = *view.error_estimate;
  if (e.layers().empty() || std::string(e.layer_name(0)) != "pt") return;
  const std::vector<double> var_w = e.layers()[0].variance_of_mean(), var_u = view.pt_raw_batches->variance_of_mean(),
                            var_d = view.pt_share_batches->variance_of_mean();
  const std::optional<ShareCorrection> share = consistent_share(s, view);
  if (var_w.empty() || var_u.empty() || var_d.empty() || !share) return;
  std::vector<double> mse(var_w.size());
  for (std::size_t i = 0; i < mse.size(); ++i) {
    const double lambda = share->lambda[i / 3], cov = 0.5 * (var_u[i] - var_w[i] - var_d[i]);
    // Not clamped: over the image the residuals' noise cancels (the relMSE); a pixel's is clamped
    // where it is shown (ImageErrorEstimate::standard_error).
    mse[i] = var_w[i] + lambda * lambda * var_d[i] + 2.0 * lambda * cov + share->left_error[i];
  }
  std::vector<float> image = view.pt_accum.mean().rgb;
  for (std::size_t i = 0; i < image.size(); ++i) image[i] += share->share.rgb[i];
  view.error_estimate->set_consistent_share(std::move(mse), std::move(image));
}

// Each view's estimate after the rounds done (closing a batch where they end one), of the image as
// written (RB's layer with --rb-level's factors), and the worst.
void update_error_estimates(RenderState& s, std::optional<std::uint64_t> rounds_done) {
  s.estimated_rel_mse = NAN;
  s.expected_worst_region_error = NAN;
  for (RenderView& view : s.views) {
    if (rounds_done) view.error_estimate->add(*rounds_done);
    if (rounds_done && view.regional_error) view.regional_error->add(*rounds_done);
    if (view.rb_level) {
      std::vector<double> factors = rb_pixel_factors(view);
      const bool regional = view.rb_level->grid().count() > 1;
      if (view.regional_error) view.regional_error->set_rb_factors(factors, regional);
      if (view.regional_error && regional) {
        RegionalError::RbLevelVariances v = view.regional_error->rb_level_relative_variances();
        view.error_estimate->set_rb_regional_level(view.regional_error->grid(), std::move(v.rb), std::move(v.corrected));
      }
      view.error_estimate->set_factors("rb", std::move(factors));
      if (view.pt_share_batches) set_consistent_error(s, view, rounds_done);
    }
    view.estimated_rel_mse = view.error_estimate->estimated_rel_mse();
    if (std::isnan(s.estimated_rel_mse) || view.estimated_rel_mse > s.estimated_rel_mse)
      s.estimated_rel_mse = view.estimated_rel_mse;
    if (view.regional_error) {
      view.expected_worst_region_error = expected_largest_error(view.regional_error->relative_standard_errors());
      if (std::isnan(s.expected_worst_region_error) || view.expected_worst_region_error > s.expected_worst_region_error)
        s.expected_worst_region_error = view.expected_worst_region_error;
    }
  }
}

// How far the render is from its error targets (--target-error, --target-block-error): the rounds
// they need, from relMSE ∝ 1/N and a region's relative error ∝ 1/√N, and the fraction done (the
// later target and the lesser fraction); unknown without a target or an estimate yet.
struct TargetProgress {
  bool known = false;
  double rounds_needed = 0.0, fraction = 1.0;
};
TargetProgress target_progress(const RenderState& s, std::uint64_t rounds_done) {
  const RenderSpec& o = s.spec;
  std::vector<double> needed_over_done;  // per target: the rounds it needs over those done
  if (o.target_error > 0.0) needed_over_done.push_back(s.estimated_rel_mse / o.target_error);
  if (o.target_block_error > 0.0) {
    const double ratio = s.expected_worst_region_error / o.target_block_error;
    needed_over_done.push_back(ratio * ratio);
  }
  TargetProgress t;
  t.known = !needed_over_done.empty();
  for (double f : needed_over_done) {
    t.known = t.known && std::isfinite(f) && f > 0.0;
    t.rounds_needed = std::max(t.rounds_needed, f * double(rounds_done));
    t.fraction = std::min(t.fraction, std::min(1.0, 1.0 / f));
  }
  // --target-error also waits for the check of RB's bias (the stop in run_render).
  if (o.target_error > 0.0 && rounds_done > 0)
    for (const RenderView& view : s.views)
      if (view.error_estimate->rb_bias_pending()) {
        const double needed = double(view.error_estimate->rb_bias_rounds_needed());
        t.rounds_needed = std::max(t.rounds_needed, needed);
        t.fraction = std::min(t.fraction, double(rounds_done) / needed);
      }
  return t;
}

// The entries of a checkpoint key ("name=value;…", checkpoint_key.h) that `other` lacks, space-separated.
std::string key_entries_not_in(const std::string& key, const std::string& other) {
  std::vector<std::string> theirs;
  for (std::size_t at = 0; at <= other.size();) {
    const std::size_t end = std::min(other.find(';', at), other.size());
    theirs.push_back(other.substr(at, end - at));
    at = end + 1;
  }
  std::string out;
  for (std::size_t at = 0; at <= key.size();) {
    const std::size_t end = std::min(key.find(';', at), key.size());
    const std::string entry = key.substr(at, end - at);
    if (!entry.empty() && std::find(theirs.begin(), theirs.end(), entry) == theirs.end())
      out += (out.empty() ? "" : " ") + entry;
    at = end + 1;
  }
  return out.empty() ? "-" : out;
}

// A resumed render starts from the checkpoint's accumulators, ray-bundle state and round count.
void resume(RenderState& s) {
  const RenderSpec& o = s.spec;
  s.key = options_key(o, s.scene.width, s.scene.height, s.scene.patch_size, s.rb ? s.rb_settings.bins : 0, s.shape,
                      s.eye_direct_shared ? "shared" : "pt") +
          views_key(o, s.scene.views);
  if (!s.resumed) return;
  Checkpoint& c = *s.resumed;
  if (c.options != s.key)
    throw UsageError("--resume " + o.resume_path + " was saved with other options: saved " +
                     key_entries_not_in(c.options, s.key) + "; now " + key_entries_not_in(s.key, c.options));
  // The key holds a walkthrough's views: the checkpoint has as many.
  if (c.further_views.size() + 1 != s.views.size())
    throw UsageError("--resume " + o.resume_path + " holds " + std::to_string(c.further_views.size() + 1) +
                     " view(s), this render has " + std::to_string(s.views.size()));
  for (std::size_t k = 0; s.ranks.root() && k < s.views.size(); ++k) {  // root's sums alone are the render's
    const std::optional<Accumulator>& pt = k ? c.further_views[k - 1].pt : c.pt;
    const std::optional<Accumulator>& rb = k ? c.further_views[k - 1].rb : c.rb;
    if (!s.pt.empty() && pt) s.views[k].pt_accum = *pt;
    if (s.rb && rb) s.views[k].rb_accum = *rb;
  }
  if (s.rb && c.rb_state) s.rb->load_state(*c.rb_state);  // every rank's chain from the saved one
  s.first_round = c.rounds;
  s.earlier_seconds = c.render_seconds;
}

// RB's error batch: --error-batch, else, under --time with the probe's costs, rb_error_batch_iterations
// of the iterations expected. Not from --spp or --iterations alone: the batch is kept in a checkpoint,
// and a render resumed to a larger count must be the uninterrupted one, its error layer included.
static std::uint64_t rb_error_batch_of(const RenderState& s) {
  const RenderSpec& o = s.spec;
  if (o.error_batch) return o.error_batch;
  if (!s.probe || !(o.seconds > 0.0) || !s.shape || s.shape->pt_alone()) return kErrorBatchRbIterations;
  return rb_error_batch_iterations(expected_pt_spp(*s.shape, o.spp, o.iterations, o.seconds, s.probe->pt_seconds_per_spp,
                                                   s.probe->rb_seconds_per_iteration) /
                                   s.shape->ratio());
}

// The error estimate (docs/design.md §9), one per view: each estimator's layer from batches of its own --
// PT's of one round, RB's of rb_error_batch_iterations in rounds.
void start_error_estimate(RenderState& s) {
  const std::uint64_t rb_batch_iterations = rb_error_batch_of(s);
  const RenderSpec& o = s.spec;
  const std::uint64_t rb_batch_rounds =
      s.shape ? (rb_batch_iterations + s.shape->rb_iterations - 1) / s.shape->rb_iterations : rb_batch_iterations;
  for (std::size_t k = 0; k < s.views.size(); ++k) {
    RenderView& view = s.views[k];
    // The image times the rounds: pt.sum / N1 + rb.sum / N2 per round (eq. 3; N1 = N2 = 1 alone).
    std::vector<ImageErrorEstimate::Layer> layers;
    if (!s.pt.empty() && (!s.shape || s.shape->pt_samples > 0))
      layers.push_back({"pt", {&view.pt_accum.sum, s.shape ? 1.0 / s.shape->pt_samples : 1.0}, 1});
    if (s.rb_renders())
      layers.push_back({"rb", {&view.rb_accum.sum, s.shape ? 1.0 / s.shape->rb_iterations : 1.0}, rb_batch_rounds});
    // A combined render checks RB's layer against PT's estimate of its share (rb_bias_rel_mse).
    std::optional<RoundSums> pt_rb_share;
    if (layers.size() == 2 && view.pt_accum.keeps_raw())
      pt_rb_share = RoundSums{&view.pt_accum.raw_sum, 1.0 / s.shape->pt_samples, &view.pt_accum.sum};
    const std::vector<BatchMeansErrorEstimate::State>* saved_states =
        !s.resumed ? nullptr : k ? &s.resumed->further_views[k - 1].error_estimate : &s.resumed->error_estimate;
    // Without --rb-level consistent's two batch states, which follow (save_checkpoint).
    std::vector<BatchMeansErrorEstimate::State> own;
    if (saved_states)
      own.assign(saved_states->begin(),
                 saved_states->end() - (view.pt_raw_batches && saved_states->size() >= 2 ? 2 : 0));
    const std::vector<BatchMeansErrorEstimate::State>* saved = saved_states ? &own : nullptr;
    // A checkpoint of before the layers were estimated apart holds one estimate of their sum, one of
    // before the check none of it: the resumed render's estimate starts afresh where that does not fit.
    if (saved && saved->size() != layers.size() + (pt_rb_share ? 1 : 0)) saved = nullptr;
    view.error_estimate.emplace(s.scene.width, s.scene.height, std::move(layers), o.error_levels, s.first_round,
                                saved, pt_rb_share);
    if (saved)  // the check's sums (zero from a checkpoint of before format 06: it pairs on from here)
      view.error_estimate->resume_rb_bias_sums(k ? s.resumed->further_views[k - 1].rb_bias_sums : s.resumed->rb_bias_sums);
    // The regional error (image/regional_error.h), on the --regions grid: RB's batches of
    // kRegionalBatchRbIterations, in rounds.
    RegionalError::Inputs in;
    if (!s.pt.empty() && (!s.shape || s.shape->pt_samples > 0)) {
      in.pt = &view.pt_accum;
      in.pt_samples = s.shape ? s.shape->pt_samples : 1;
    }
    if (s.rb_renders()) {
      in.rb = &view.rb_accum;
      in.rb_iterations = s.shape ? s.shape->rb_iterations : 1;
      in.rb_batch_rounds = (kRegionalBatchRbIterations + in.rb_iterations - 1) / in.rb_iterations;
    }
    const std::optional<RegionalError::State> none;
    const std::optional<RegionalError::State>& saved_regional =
        !s.resumed ? none : k ? s.resumed->further_views[k - 1].regional_error : s.resumed->regional_error;
    const RegionGrid grid = RegionGrid::over(s.scene.width, s.scene.height, o.regions, o.regions);
    try {
      view.regional_error.emplace(grid, in, s.first_round, saved_regional);
    } catch (const std::runtime_error&) {  // a checkpoint of another grid, or of before format 05: afresh
      view.regional_error.emplace(grid, in, s.first_round, std::nullopt);
    }
  }
  update_error_estimates(s, std::nullopt);
}

// --rb-level corrected (image/rb_level.h): the levels of RB's layer and of PT's estimate of it,
// batched like the render loop's batches.
void start_rb_levels(RenderState& s) {
  if (!rb_level_corrected(s.spec) || !s.shape || s.shape->pt_samples == 0 || !s.rb_renders()) return;
  for (std::size_t k = 0; k < s.views.size(); ++k) {
    RenderView& view = s.views[k];
    const std::optional<RbLevel::State> none;
    const std::optional<RbLevel::State>& saved =
        !s.resumed ? none : k ? s.resumed->further_views[k - 1].rb_level : s.resumed->rb_level;
    const int regions = rb_level_regions(s.spec);
    view.rb_level.emplace(RegionGrid::over(s.scene.width, s.scene.height, regions, regions), s.first_round,
                          view.pt_accum, s.shape->pt_samples, view.rb_accum, s.shape->rb_iterations, saved);
    if (!rb_share_consistent(s.spec)) continue;
    // PT's u and d in batches of a round. A checkpoint keeps their states after the error estimate's
    // (save_checkpoint); one of another level has none, and they start from the rounds this run
    // renders (the earlier rounds count in the means, not in the variances' batches).
    const std::vector<BatchMeansErrorEstimate::State>* saved_batches =
        !s.resumed ? nullptr : k ? &s.resumed->further_views[k - 1].error_estimate : &s.resumed->error_estimate;
    if (saved_batches && saved_batches->size() >= 2 && saved_batches->back().width == s.scene.width &&
        saved_batches->back().height == s.scene.height) {
      view.pt_raw_batches.emplace(BatchMeansErrorEstimate::from_state((*saved_batches)[saved_batches->size() - 2],
                                                                      s.scene.width, s.scene.height));
      view.pt_share_batches.emplace(
          BatchMeansErrorEstimate::from_state(saved_batches->back(), s.scene.width, s.scene.height));
      continue;
    }
    const RoundSums u = pt_raw_round_sums(s, view), d = pt_share_round_sums(s, view);
    view.pt_raw_batches.emplace(s.scene.width, s.scene.height, 1, 1, s.first_round, s.first_round ? &u : nullptr);
    view.pt_share_batches.emplace(s.scene.width, s.scene.height, 1, 1, s.first_round, s.first_round ? &d : nullptr);
  }
}

void save_checkpoint(RenderState& s, std::uint64_t rounds, double seconds) {
  Checkpoint c;
  c.options = s.key;
  c.rounds = rounds;
  c.render_seconds = s.earlier_seconds + seconds;
  for (std::size_t k = 0; k < s.views.size(); ++k) {
    const RenderView& view = s.views[k];
    Checkpoint::View saved;
    if (!s.pt.empty()) saved.pt = view.pt_accum;
    if (s.rb) saved.rb = view.rb_accum;
    saved.error_estimate = view.error_estimate->state();
    if (view.pt_raw_batches) {  // --rb-level consistent's batches after the estimate's own (start_rb_levels)
      saved.error_estimate.push_back(view.pt_raw_batches->state());
      saved.error_estimate.push_back(view.pt_share_batches->state());
    }
    saved.rb_bias_sums = view.error_estimate->rb_bias_sums();
    if (view.rb_level) saved.rb_level = view.rb_level->state();
    saved.regional_error = view.regional_error->state();
    if (k) {
      c.further_views.push_back(std::move(saved));
    } else {
      c.pt = std::move(saved.pt);
      c.rb = std::move(saved.rb);
      c.error_estimate = std::move(saved.error_estimate);
      c.rb_bias_sums = saved.rb_bias_sums;
      c.rb_level = std::move(saved.rb_level);
      c.regional_error = std::move(saved.regional_error);
    }
  }
  if (s.rb) c.rb_state = s.rb->save_state();
  write_checkpoint(s.spec.checkpoint_path, c);
}

// Each view's first-hit albedo and normal (the EXR's albedo and normal layers), on root's first
// device; with --denoise prefiltered, and the time they and the beauty's denoise will take kept out of
// --time's rounds (kDenoiseCostOverPrefilter).
void prepare_features(RenderState& s) {
  if (!s.ranks.root()) return;
  const auto start = std::chrono::steady_clock::now();
  double prefilter_seconds = 0.0;
  const RenderDevice& device = *s.devices.front();
  for (RenderView& view : s.views) {
    view.features = render_first_hit_features(device.context, device.scene, view.camera, s.kernel_options);
    if (!s.denoiser) continue;
    const auto before = std::chrono::steady_clock::now();
    view.prefiltered = view.features;
    s.denoiser->prefilter(view.prefiltered.albedo, view.prefiltered.normal);
    prefilter_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count();
  }
  s.denoise_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.beauty_denoise_seconds = kDenoiseCostOverPrefilter * prefilter_seconds;
  if (s.denoiser) s.reserved_seconds = s.denoise_seconds + s.beauty_denoise_seconds;
}

// --save-every: every view's image files as they stand, written atomically like the final ones;
// denoised where that takes under a tenth of the interval (else the raw image: said once).
void save_images_so_far(RenderState& s, RenderObserver& observer, bool& said_raw) {
  const bool denoise = s.denoiser && s.beauty_denoise_seconds < 0.1 * s.spec.save_every;
  if (s.denoiser && !denoise && !said_raw) {
    observer.note(printf_text("--save-every: the images saved while rendering are the raw ones (denoising "
                              "takes about %.1f s, more than a tenth of %g s); the final image is denoised",
                              s.beauty_denoise_seconds, s.spec.save_every));
    said_raw = true;
  }
  for (const RenderView& view : s.views) {
    RenderLayers layers = make_layers(s, view);
    if (denoise) denoise_image(*s.denoiser, view, layers);
    write_images(s, view, layers);
  }
}

// What the render loop runs, and its round target.
void build_schedule(RenderState& s) {
  const RenderSpec& o = s.spec;
  s.pass = !s.pt.empty() ? static_cast<ProgressivePass*>(s.pt.front().get()) : s.rb.get();
  if (s.walkthrough() && !s.pt.empty()) {  // every view's path tracer, the same samples
    std::vector<ProgressivePass*> views;
    for (auto& pt : s.pt) views.push_back(pt.get());
    s.each_view_pt = std::make_unique<EachViewPass>(std::move(views));
    s.pass = s.each_view_pt.get();
  }
  s.rounds = o.mode == "rb" ? o.iterations : o.spp;
  if (s.several_devices()) {
    std::vector<DeviceLane> lanes;
    for (std::size_t i = 0; i < s.devices.size(); ++i) {
      DeviceLane lane;
      lane.device_index = s.devices[i]->context.info.index;
      lane.device_name = s.devices[i]->context.info.device_name;
      for (std::size_t k = 0; k < s.roles.pt.size(); ++k)
        if (s.roles.pt[k] == i) {
          lane.pt = s.pt[k].get();
          lane.accum = s.pt_pass_accums[k];
        }
      if (s.rb && s.roles.rb == i && !lane.pt) {
        lane.rb = s.rb.get();
        lane.accum = s.rb_pass_accum;
      }
      if (lane.pt || lane.rb) lanes.push_back(lane);
    }
    auto parallel = std::make_unique<ParallelPass>(std::move(lanes), s.shape, s.pt_rank_accum(), s.rb_rank_accum());
    s.lanes = parallel.get();
    s.pass = parallel.get();
    s.schedule = std::move(parallel);
  } else if (s.shape) {
    ProgressivePass& pt = s.each_view_pt ? *s.each_view_pt : static_cast<ProgressivePass&>(*s.pt.front());
    s.schedule = std::make_unique<CombinedPass>(pt, *s.rb, *s.shape);
    s.pass = s.schedule.get();
  }
  if (s.several_ranks()) {
    std::vector<RankSums> sums;
    if (!s.pt.empty()) sums.push_back(RankSums{&s.pt_rank_accum(), &s.first_view().pt_accum});
    if (s.rb) sums.push_back(RankSums{&s.rb_rank_accum(), &s.first_view().rb_accum});
    s.rank_schedule = std::make_unique<RankPass>(*s.pass, s.ranks, std::move(sums));
    s.pass = s.rank_schedule.get();
  }
  if (s.shape) {
    // PT alone (auto, never with --iterations: passes/combined.h) counts samples only.
    s.rounds = o.spp                    ? (o.spp + s.shape->pt_samples - 1) / s.shape->pt_samples
               : s.shape->pt_alone() ? 0
                                        : (o.iterations + s.shape->rb_iterations - 1) / s.shape->rb_iterations;
    if (o.equal_time_spp) {  // from root's probe, the same on every rank
      s.rounds = equal_time_rounds(o.equal_time_spp, *s.shape, s.probe ? s.probe->pt_seconds_per_spp : 0.0,
                                   s.probe ? s.probe->rb_seconds_per_iteration : 0.0);
      s.ranks.broadcast(s.rounds);
    }
  }
}

std::string device_description(const RenderState& s) {
  std::string out;
  for (const auto& d : s.devices) out += (out.empty() ? "" : " + ") + d->context.description();
  return out;
}

void render_rounds(RenderState& s, RenderObserver& observer) {
  const RenderSpec& o = s.spec;
  std::uint64_t saved_rounds = s.first_round;
  double last_save = 0.0, last_image_save = 0.0;
  bool said_raw = false;
  // Every rank starts the rounds together, so that a Ctrl-C once root has started finds every rank
  // ready to stop (its handler installed), however long its kernel builds took.
  s.ranks.wait_for_all();
  observer.started();
  const PatchClusters& clusters = s.scene.patches.clusters;
  std::string clustered = clusters.clusters > 0 ? printf_text(" (%zu of the triangles in %zu clusters)",
                                                         clusters.clustered_triangles, clusters.clusters)
                                           : "";
  const LightRefinementResult& refined = s.scene.refinement;
  if (refined.refined_triangles > 0)
    clustered += printf_text(" (%u before %zu triangles were split where shadows cross them%s)", refined.patches_before,
                             refined.refined_triangles, refined.budget_reached ? ", up to the budget" : "");
  observer.note(printf_text("rendering %s (%dx%d, %s%s, %zu triangles, %u patches%s) on %s", o.scene.c_str(),
                            s.scene.width, s.scene.height, o.mode.c_str(),
                            s.shape ? (", weights " + o.weights).c_str() : "", s.scene.scene.triangles.size(),
                            s.scene.patches.patch_count, clustered.c_str(), device_description(s).c_str()));
  for (std::size_t i : s.roles.idle)
    observer.note("warning: --mode " + o.mode + " runs on one device: " + s.devices[i]->context.info.device_name +
                  " stays idle");
  const double pixels = double(s.scene.width) * s.scene.height;
  const bool counts_iterations = o.mode == "rb" || (s.shape && s.shape->pt_samples == 0);
  const double samples_per_round = counts_iterations ? (s.shape ? s.shape->rb_iterations : 1.0)
                                                     : (s.shape ? s.shape->pt_samples * pixels : pixels);
  // On several ranks root alone decides when the time or --target-error ends the render; every rank
  // stops at the round they agree on (rounds and Ctrl-C on any rank, else root's reason).
  // --time holds what comes after the rounds too (--denoise): they get the rest, at least a tenth.
  const double round_seconds = o.seconds > 0.0 ? std::max(o.seconds - s.reserved_seconds, 0.1 * o.seconds) : 0.0;
  RenderBudget budget{s.rounds, s.ranks.root() ? round_seconds : 0.0, {}};
  if (s.several_ranks())
    budget.agree_stop = [&](LoopStop stop) { return LoopStop(s.ranks.max_over_ranks(int(stop))); };
  // --target-error: done once every view's estimate has the degrees of freedom to say that the
  // relMSE is at most X (checked after each batch).
  // --target-block-error likewise, on the expected worst region's relative error.
  if ((o.target_error > 0.0 || o.target_block_error > 0.0) && s.ranks.root())
    budget.target_reached = [&] {
      for (const RenderView& view : s.views) {
        if (o.target_error > 0.0 && view.error_estimate->degrees_of_freedom() < kMinDegreesOfFreedomForTarget)
          return false;
        // Nor before RB's bias is checked: until then the estimate cannot hold it (rb_bias_pending).
        if (o.target_error > 0.0 && view.error_estimate->rb_bias_pending()) return false;
        if (o.target_block_error > 0.0 && view.regional_error->degrees_of_freedom() < kMinDegreesOfFreedomForTarget)
          return false;
      }
      return (o.target_error <= 0.0 || s.estimated_rel_mse <= o.target_error) &&
             (o.target_block_error <= 0.0 || s.expected_worst_region_error <= o.target_block_error);
    };
  s.outcome = run_progressive(
      *s.pass, budget, observer.stop_requested(),
      [&](const RenderProgress& p) {
        if (!s.ranks.root()) return;  // its accumulators hold its last batch only
        double secs = std::max(p.elapsed_seconds, 1e-9);
        for (RenderView& view : s.views)
          if (view.rb_level) view.rb_level->add(p.rounds_done);
        update_error_estimates(s, p.rounds_done);
        RenderProgressReport report;
        report.frames = s.views.size();
        report.fraction = p.fraction;
        const TargetProgress target = target_progress(s, p.rounds_done);
        if (target.known && p.rounds_done > s.first_round) {
          const double seconds_per_round = p.elapsed_seconds / double(p.rounds_done - s.first_round);
          double eta = std::max(0.0, target.rounds_needed - double(p.rounds_done)) * seconds_per_round;
          if (o.seconds > 0.0) eta = std::min(eta, std::max(0.0, o.seconds - p.elapsed_seconds));
          report.eta_seconds = eta;
          report.fraction = std::max(report.fraction, target.fraction);
        }
        report.rate = double(p.rounds_done - s.first_round) * samples_per_round / secs;
        report.mrays_per_second = double(p.rays) / secs * 1e-6;
        report.elapsed_seconds = p.elapsed_seconds;
        report.rate_unit = counts_iterations ? "iterations/s" : "samples/s";
        report.estimated_rel_mse = s.estimated_rel_mse;
        observer.progress(report);
        if (!o.checkpoint_path.empty() && p.elapsed_seconds - last_save >= o.checkpoint_every) {
          save_checkpoint(s, p.rounds_done, p.elapsed_seconds);
          saved_rounds = p.rounds_done;
          last_save = p.elapsed_seconds;
        }
        if (o.save_every > 0.0 && p.elapsed_seconds - last_image_save >= o.save_every) {
          save_images_so_far(s, observer, said_raw);
          last_image_save = p.elapsed_seconds;
        }
      },
      s.first_round);
  observer.finished();
  // After a device failed its passes are past the rounds the accumulators hold: the checkpoint keeps
  // its last save.
  if (!s.outcome.failure.empty()) return;
  if (s.ranks.root() && !o.checkpoint_path.empty() && (saved_rounds != s.outcome.rounds || o.resume_path.empty()))
    save_checkpoint(s, s.outcome.rounds, s.outcome.seconds);
}

// Samples and iterations of the whole render, and each device's part of it (this rank's devices).
void count_work(RenderState& s, RenderResult& r) {
  auto pt_samples = [&](std::uint64_t rounds) -> std::uint64_t {
    return s.shape ? rounds * s.shape->pt_samples : !s.pt.empty() ? rounds : 0;
  };
  auto rb_iterations = [&](std::uint64_t rounds) -> std::uint64_t {
    return s.shape ? rounds * s.shape->rb_iterations : s.rb ? rounds : 0;
  };
  r.pt_samples = pt_samples(s.outcome.rounds);
  r.rb_iterations = rb_iterations(s.outcome.rounds);
  r.device_failure = s.outcome.failure;
  if (!s.lanes) {  // one device: all of it (a resumed render's earlier runs too), or this rank's part
    const DeviceInfo& info = s.devices.front()->context.info;
    const std::uint64_t rounds = s.rank_schedule ? s.rank_schedule->rank_rounds() : s.outcome.rounds;
    r.devices.push_back(DeviceWorkReport{info.index, info.device_name, pt_samples(rounds), rb_iterations(rounds),
                                         s.outcome.seconds});
    return;
  }
  for (const auto& device : s.devices) {  // in --device's order; an idle one did nothing
    const DeviceInfo& info = device->context.info;
    DeviceWorkReport report{info.index, info.device_name, 0, 0, 0.0};
    for (const DeviceLane& lane : s.lanes->lanes())
      if (lane.device_index == info.index)
        report = DeviceWorkReport{info.index, lane.device_name, lane.pt_samples, lane.rb_iterations, lane.busy_seconds};
    r.devices.push_back(report);
  }
}

}  // namespace

RenderJob::RenderJob(const RenderSpec& spec, const Ranks& ranks) : spec_(spec), ranks_(ranks) {}
RenderJob::~RenderJob() = default;

RenderResult RenderJob::run(RenderObserver& observer) {
  RenderState s(spec_, ranks_);
  if (spec_.denoise && ranks_.root()) {  // before the scene: a missing library is a usage error, found at once
    try {
      s.denoiser = Denoiser::open();
    } catch (const DenoiserUnavailable& e) {
      throw UsageError(e.what());
    }
  }
  s.scene = prepare_scene(spec_, [&](const std::string& line) { observer.note(line); });
  choose_round(s);
  open_devices(s);
  build_passes(s);
  if (!spec_.resume_path.empty()) s.resumed = read_checkpoint(spec_.resume_path);
  choose_auto_settings(s, observer);
  resume(s);
  start_rb_levels(s);
  start_error_estimate(s);
  build_schedule(s);
  prepare_features(s);
  render_rounds(s, observer);

  RenderResult r;
  r.outcome = s.outcome;
  r.width = s.scene.width;
  r.height = s.scene.height;
  r.combined = s.shape.has_value();
  r.eye_direct_shared = r.combined && s.eye_direct_shared;
  r.consistent = s.first_view().pt_share_batches.has_value();
  r.mrays_per_second = s.outcome.seconds > 0 ? double(s.outcome.rays) / s.outcome.seconds * 1e-6 : 0.0;
  r.estimated_rel_mse = s.estimated_rel_mse;
  r.expected_worst_region_error = s.expected_worst_region_error;
  r.region_degrees_of_freedom = s.first_view().regional_error->degrees_of_freedom();
  r.region_columns = s.first_view().regional_error->grid().columns;
  r.region_rows = s.first_view().regional_error->grid().rows;
  const ImageErrorEstimate& e = *s.first_view().error_estimate;
  r.rb_bias_rel_mse = e.rb_bias_rel_mse();
  r.rb_bias_pending = e.rb_bias_pending();
  r.rb_bias_paired_batches = e.rb_bias_check().batches;
  for (std::size_t l = 0; l < e.layers().size(); ++l)
    r.error_layers.push_back({e.layer_name(l), e.layers()[l].batches(), e.layers()[l].batch_rounds()});
  count_work(s, r);
  r.ranks = s.ranks.size();
  if (!s.ranks.root()) return r;  // root alone holds the render's sums and writes its files
  const auto outputs_start = std::chrono::steady_clock::now();
  for (const RenderView& view : s.views) {
    RenderLayers layers = make_layers(s, view);
    if (s.denoiser) denoise_image(*s.denoiser, view, layers);
    RenderFrame frame = write_images(s, view, layers);
    frame.estimated_rel_mse = view.estimated_rel_mse;
    if (r.frames.empty()) {
      r.reference_metrics = compare_layers(s, layers);
      r.exr_path = frame.exr_path;
      r.png_path = frame.png_path;
      r.layers = std::move(layers.images);
    }
    r.frames.push_back(frame);
  }
  r.denoised = s.denoiser != nullptr;
  r.denoise_seconds = s.denoise_seconds;
  if (s.denoiser)  // the beauty's denoise, timed with the files written
    r.denoise_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - outputs_start).count();
  if (!spec_.video_path.empty()) encode_video(s, r);
  r.stats = render_stats(s, r);
  if (!spec_.stats_path.empty()) write_json_file(spec_.stats_path, r.stats);
  return r;
}

}  // namespace bp
