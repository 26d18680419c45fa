// A one-line progress bar on stderr: percentage, samples/s, Mrays/s and ETA. Silent when stderr is
// not a terminal (logs and CI stay clean).
#pragma once
#include <string>

namespace bp {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  void update(double fraction, double rate, double mrays_per_second, double elapsed_seconds,
              const char* rate_unit = "samples/s");
  void finish();  // ends the line
  bool enabled() const { return enabled_; }

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
};

std::string format_duration(double seconds);

}  // namespace bp
