// One render as an object (docs/design.md §8, §10): built from a RenderSpec -- scene, devices, passes,
// budget, outputs -- and run with an observer that hears its notes and progress and can stop it.
// The CLI, MPI ranks and walkthrough views drive renders through this; none of them wires passes.
#pragma once
#include "image/image.h"
#include "passes/render_loop.h"
#include "render/ranks.h"
#include "render/render_spec.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace bp {

// What a progress line shows, after each batch.
struct RenderProgressReport {
  double fraction = 0.0;           // of the budget (rounds, time or --target-error)
  double rate = 0.0;               // samples (or iterations) per second in this run
  const char* rate_unit = "samples/s";
  double mrays_per_second = 0.0;
  double elapsed_seconds = 0.0;
  double estimated_rel_mse = NAN;  // the worst frame's; NaN before two error-estimate batches
  double eta_seconds = NAN;        // NaN: from the fraction
  std::size_t frames = 1;          // views rendered together (a walkthrough's frames)
};

class RenderObserver {
 public:
  virtual ~RenderObserver() = default;
  // A line for the person running it (warnings, the choices --ratio auto and --eye-direct auto made).
  virtual void note(const std::string& line) { (void)line; }
  // Everything is built and the first counted round is next.
  virtual void started() {}
  virtual void progress(const RenderProgressReport& report) { (void)report; }
  // The last round is done; the files are written next.
  virtual void finished() {}
  // Read between batches: once true, the render stops after the current batch.
  virtual const std::atomic<bool>& stop_requested() = 0;
};

// One device's part of the render (the stats' "devices").
struct DeviceWorkReport {
  int index = 0;                                    // as `bundlepath devices` lists it
  std::string name;
  std::uint64_t pt_samples = 0, rb_iterations = 0;  // samples per pixel / iterations it rendered
  double busy_seconds = 0.0;                        // time its passes ran
};

// One view's image files (a walkthrough's frame k: PREFIX_000k.exr, .png).
struct RenderFrame {
  std::string exr_path, png_path;
  double estimated_rel_mse = NAN;
};

struct RenderResult {
  RenderOutcome outcome;
  int width = 0, height = 0;
  std::uint64_t pt_samples = 0, rb_iterations = 0;  // over the whole render (resumed ones included)
  bool combined = false;                            // PT and RB together (--mode combined)
  bool eye_direct_shared = false;                   // combined: the eye vertex's direct light shared with RB
  bool consistent = false;  // --rb-level consistent: RB's share corrected by PT's, its left bias in the estimate
  double mrays_per_second = 0.0;
  std::string exr_path, png_path;
  std::vector<std::pair<std::string, ErrorMetrics>> reference_metrics;  // per layer, with --reference
  double estimated_rel_mse = NAN;  // a walkthrough: its worst frame's
  double rb_bias_rel_mse = NAN;    // the first view's part of it from RB's bias (ImageErrorEstimate); NaN: not checked
  bool rb_bias_pending = false;    // a combined render's check not counted yet (too few of RB's batches paired)
  std::uint64_t rb_bias_paired_batches = 0;  // RB's batches the check has paired so far
  // The regional error (image/regional_error.h): the expected worst region's relative error and the
  // grid (a walkthrough: its worst frame's); NaN before two batches.
  double expected_worst_region_error = NAN;
  double region_degrees_of_freedom = 0.0;  // the first view's (RegionalError::degrees_of_freedom)
  int region_columns = 0, region_rows = 0;
  struct ErrorLayer {  // the estimate's batches per estimator's layer (image/error_estimate.h)
    std::string name;   // "pt", "rb"
    std::uint64_t batches = 0, batch_rounds = 0;
  };
  std::vector<ErrorLayer> error_layers;
  std::vector<DeviceWorkReport> devices;            // this rank's
  int ranks = 1;                                    // the processes that rendered it (MPI ranks)
  std::vector<RenderFrame> frames;  // one per view, in order (a plain render: one, its exr and png paths)
  std::string video_path;           // --video, once encoded
  // The (first frame's) image's layers as written ("" the combined image; render_outputs.h), and the
  // stats (written to --stats when given).
  std::vector<std::pair<std::string, ImageRGB>> layers;
  nlohmann::json stats;
  std::string device_failure;  // empty, or which device failed mid-render and why (the image is what was done)
  bool denoised = false;        // --denoise: the main layers and the PNG are OpenImageDenoise's; raw.* the render's
  double denoise_seconds = 0.0;  // the features, their prefilter and the denoise, on top of outcome.seconds
};

class RenderJob {
 public:
  // ranks: the processes rendering this image together (render/ranks.h); root alone writes files,
  // notes and reports progress.
  explicit RenderJob(const RenderSpec& spec, const Ranks& ranks = Ranks());
  ~RenderJob();
  RenderJob(const RenderJob&) = delete;
  RenderJob& operator=(const RenderJob&) = delete;

  // Loads, builds, renders and writes the outputs (image files, stats, checkpoint). Throws
  // UsageError for a spec that cannot make this render, SceneError, DeviceError, std::runtime_error.
  RenderResult run(RenderObserver& observer);

 private:
  RenderSpec spec_;
  Ranks ranks_;
};

}  // namespace bp
