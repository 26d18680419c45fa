// A one-line progress bar on stderr: percentage, samples/s, Mrays/s, the estimated relMSE and ETA.
// Silent when stderr is not a terminal (logs and CI stay clean).
#pragma once
#include <cmath>
#include <string>

namespace bp {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  // estimated_rel_mse: NaN hides it; eta_seconds: NaN takes it from the fraction.
  void update(double fraction, double rate, double mrays_per_second, double elapsed_seconds,
              const char* rate_unit = "samples/s", double estimated_rel_mse = NAN, double eta_seconds = NAN);
  void finish();  // ends the line
  bool enabled() const { return enabled_; }

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
};

std::string format_duration(double seconds);

}  // namespace bp
