#include "cli/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace bp {

std::string format_duration(double s) {
  char buf[32];
  if (!std::isfinite(s) || s < 0) return "--:--";
  long t = long(s + 0.5);
  if (t >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else std::snprintf(buf, sizeof buf, "%02ld:%02ld", t / 60, t % 60);
  return buf;
}

ProgressBar::ProgressBar(std::string label) : label_(std::move(label)), enabled_(::isatty(STDERR_FILENO) == 1) {}

void ProgressBar::update(double fraction, double rate, double mrays_per_second, double elapsed, const char* rate_unit,
                         double estimated_rel_mse, double eta_seconds) {
  if (!enabled_) return;
  const int width = 30;
  int filled = int(std::lround(std::clamp(fraction, 0.0, 1.0) * width));
  std::string bar(std::size_t(filled), '#');
  bar.resize(width, '.');
  double eta = !std::isnan(eta_seconds) ? eta_seconds : fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : NAN;
  char error[48] = "";
  if (std::isfinite(estimated_rel_mse)) std::snprintf(error, sizeof error, "  relMSE~%.2e", estimated_rel_mse);
  std::fprintf(stderr, "\r%s [%s] %5.1f%%  %.3g %s  %.2f Mrays/s%s  ETA %s ", label_.c_str(), bar.c_str(),
               fraction * 100.0, rate, rate_unit, mrays_per_second, error, format_duration(eta).c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (enabled_ && drawn_) std::fputc('\n', stderr);
  drawn_ = false;
}

}  // namespace bp
