// bundlepath render: the options go to a RenderJob (render/render_job.h); this prints its notes,
// its progress bar and its summary (on MPI rank 0 only), and turns the result into an exit code.
#include "cli/commands.h"

#include "cli/interrupt.h"
#include "cli/progress.h"
#include "image/error_estimate.h"
#include "render/render_job.h"

#include <cmath>
#include <cstdio>
#include <optional>

namespace bp {
namespace {

// The end line's hint: RB's bias (ImageErrorEstimate::rb_bias_rel_mse) past this share of the
// estimated relMSE (the glossy box at its 10 s defaults: 0.0018-0.0028 of 0.0029-0.0044).
constexpr double kRbBiasHintShare = 0.5;

class CliObserver : public RenderObserver {
 public:
  // speaks: this process prints (MPI rank 0, or the only process); every rank hears Ctrl-C.
  CliObserver(std::string mode, bool speaks) : mode_(std::move(mode)), speaks_(speaks) {}
  void note(const std::string& line) override {
    if (speaks_) std::fprintf(stderr, "bundlepath: %s\n", line.c_str());
  }
  void started() override { install_interrupt_handlers(speaks_); }
  void progress(const RenderProgressReport& p) override {
    if (!speaks_) return;
    if (!bar_) bar_.emplace(p.frames > 1 ? mode_ + " " + std::to_string(p.frames) + " frames" : mode_);
    bar_->update(p.fraction, p.rate, p.mrays_per_second, p.elapsed_seconds, p.rate_unit, p.estimated_rel_mse,
                 p.eta_seconds);
  }
  void finished() override {
    if (bar_) bar_->finish();
  }
  const std::atomic<bool>& stop_requested() override { return bp::stop_requested(); }

 private:
  std::string mode_;
  bool speaks_;
  std::optional<ProgressBar> bar_;
};

void print_summary(const RenderOptions& o, const RenderResult& r) {
  for (const auto& [key, m] : r.reference_metrics)
    std::fprintf(stderr, "bundlepath: %-8s vs reference: relMSE %.4g  RMSE %.4g  mean bias %+.4g\n", key.c_str(),
                 m.rel_mse, m.rmse, m.mean_bias);
  const std::string done = r.combined ? std::to_string(r.pt_samples) + " spp + " +
                                            std::to_string(r.rb_iterations) + " iterations"
                           : o.mode != "rb" ? std::to_string(r.pt_samples) + " spp"
                                            : std::to_string(r.rb_iterations) + " iterations";
  std::fprintf(stderr, "bundlepath: %s%s at %dx%d in %.2f s (%.2f Mrays/s) -> %s, %s\n",
               r.outcome.interrupted ? "interrupted after " : !r.device_failure.empty() ? "stopped after " : "",
               done.c_str(), r.width, r.height, r.outcome.seconds, r.mrays_per_second, r.exr_path.c_str(),
               r.png_path.c_str());
  if (r.frames.size() > 1)
    std::fprintf(stderr, "bundlepath: %zu frames: %s ... %s%s%s\n", r.frames.size(), r.frames.front().exr_path.c_str(),
                 r.frames.back().exr_path.c_str(), r.video_path.empty() ? "" : ", video ", r.video_path.c_str());
  std::string batches;  // "12 batches of at least 1 round", or per layer: "PT 12 ... + RB 3 ..."
  for (const RenderResult::ErrorLayer& l : r.error_layers) {
    const std::string name = l.name == "pt" ? "PT" : "RB";
    batches += (batches.empty() ? "" : " + ") + (r.error_layers.size() > 1 ? name + " " : std::string()) +
               std::to_string(l.batches) + (l.batches == 1 ? " batch" : " batches") + " of at least " +
               std::to_string(l.batch_rounds) +
               (l.batch_rounds == 1 ? " round" : " rounds");
  }
  // RB's bias as far as PT sees it (ImageErrorEstimate::rb_bias_rel_mse): a combined render's.
  char bias[160] = "";
  if (o.mode == "rb")  // nothing estimates RB's patch-level bias without the path tracer
    std::snprintf(bias, sizeof bias, "; noise only: the ray bundles' bias from their patches is not in it");
  else if (r.consistent)  // the correction's own estimate holds what is left of RB's bias (image/share_correction.h)
    std::snprintf(bias, sizeof bias, "; the ray bundles' share corrected by the path tracer's, what is left of its "
                  "bias included");
  else if (r.rb_bias_rel_mse > 0.0)
    std::snprintf(bias, sizeof bias, "; the ray bundles' bias, as the path tracer sees it: %.2g", r.rb_bias_rel_mse);
  else if (r.rb_bias_rel_mse == 0.0)
    std::snprintf(bias, sizeof bias, "; no ray-bundle bias seen");
  else if (r.rb_bias_pending)  // too short a render to check RB's bias: say that the estimate lacks it
    std::snprintf(bias, sizeof bias, "; the ray bundles' bias not checked yet, not included (%llu of %llu batch pairs)",
                  static_cast<unsigned long long>(r.rb_bias_paired_batches),
                  static_cast<unsigned long long>(kRbBiasMinPairedBatches));
  if (r.denoised)
    std::fprintf(stderr, "bundlepath: denoised by OpenImageDenoise in %.2f s (albedo and normal, prefiltered); the raw "
                 "image is the EXR's raw layers, and the error estimates below are of it, not of the denoised one\n",
                 r.denoise_seconds);
  if (std::isfinite(r.estimated_rel_mse))
    std::fprintf(stderr, "bundlepath: estimated relMSE %.3g%s%s (noise from %s%s)%s\n",
                 r.estimated_rel_mse, r.denoised ? " of the raw image" : "", r.frames.size() > 1 ? " (worst frame)" : "",
                 batches.c_str(), bias,
                 o.target_error > 0.0 ? (r.outcome.target_reached ? ": --target-error reached"
                                                                  : ": --target-error not reached")
                                      : "");
  else if (!r.error_layers.empty())  // the noise is the batches' spread: one has none; silence would read as none
    std::fprintf(stderr, "bundlepath: no error estimate: it needs two batches or more and this render held %s; render longer "
                 "(--time, --spp) for one\n", batches.c_str());
  // Where RB's bias is most of the error, more samples of the same mix will not remove it: say what will.
  // With the eye vertex's direct light shared, first that: RB's patch-level eye light is most of its
  // bias there (docs/results.md, "Who takes the eye vertex's direct light").
  if (!r.consistent && r.rb_bias_rel_mse > kRbBiasHintShare * r.estimated_rel_mse)
    std::fprintf(stderr, "bundlepath: the ray bundles' bias is %.0f %% of that error and does not shrink with time; %smore of the "
                 "time for the path tracer (a larger --ratio, or --mode pt) lowers it\n",
                 100.0 * r.rb_bias_rel_mse / r.estimated_rel_mse,
                 r.eye_direct_shared ? "the first hit's direct light for the path tracer alone (--eye-direct pt), or " : "");
  // Fewer degrees of freedom than a target waits for: the estimate is rough, and a region may be off
  // by several of its reported errors.
  char rough[96] = "";
  if (r.region_degrees_of_freedom < kMinDegreesOfFreedomForTarget)
    std::snprintf(rough, sizeof rough, "; rough, from %.0f degrees of freedom: render longer", r.region_degrees_of_freedom);
  if (std::isfinite(r.expected_worst_region_error))
    std::fprintf(stderr, "bundlepath: worst of %dx%d regions expected off by %.2f %% (mean luminance; --stats has each%s)%s\n",
                 r.region_columns, r.region_rows, 100.0 * r.expected_worst_region_error, rough,
                 o.target_block_error > 0.0 ? (r.outcome.target_reached ? ": --target-block-error reached"
                                                                        : ": --target-block-error not reached")
                                            : "");
  if (r.outcome.nonfinite_samples)
    std::fprintf(stderr, "bundlepath: warning: %llu NaN/Inf samples were dropped\n",
                 static_cast<unsigned long long>(r.outcome.nonfinite_samples));
  if (!r.device_failure.empty())
    std::fprintf(stderr, "bundlepath: error: %s; the image holds the rounds completed before it\n",
                 r.device_failure.c_str());
}

}  // namespace

int run_render(const RenderOptions& o, const Ranks& ranks) {
  CliObserver observer(o.mode, ranks.root());
  RenderJob job(o, ranks);
  const RenderResult result = job.run(observer);
  if (ranks.root()) print_summary(o, result);
  if (!result.device_failure.empty()) return 1;
  return result.outcome.interrupted ? 130 : 0;
}

}  // namespace bp
