#include "passes/checkpoint.h"
#include "image/atomic_file.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace bp {
namespace {

constexpr char kMagic[8] = {'B', 'P', 'C', 'K', 'P', 'T', '0', '6'};
// Versions 01 (it ends before the error estimate's statistics), 02 (before --rb-level: it ends
// before the RB level's), 03 (one error estimate of the layers' sum, not one per layer), 04 (no
// regional error) and 05 (no sums of the check of RB's layer) are read too.
constexpr char kMagicV1[8] = {'B', 'P', 'C', 'K', 'P', 'T', '0', '1'};
constexpr char kMagicV2[8] = {'B', 'P', 'C', 'K', 'P', 'T', '0', '2'};
constexpr char kMagicV3[8] = {'B', 'P', 'C', 'K', 'P', 'T', '0', '3'};
constexpr char kMagicV4[8] = {'B', 'P', 'C', 'K', 'P', 'T', '0', '4'};
constexpr char kMagicV5[8] = {'B', 'P', 'C', 'K', 'P', 'T', '0', '5'};
// A walkthrough's further views follow the first's RB level, after this tag (a plain render's
// checkpoint ends before it).
constexpr char kViewsTag[8] = {'V', 'I', 'E', 'W', 'S', '0', '0', '1'};

struct Writer {
  std::string bytes;
  template <class T>
  void value(const T& v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof v); }
  template <class T>
  void array(const std::vector<T>& v) {
    value(std::uint64_t(v.size()));
    if (!v.empty()) bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void text(const std::string& s) { array(std::vector<char>(s.begin(), s.end())); }
};

struct Reader {
  const std::string& bytes;
  const std::string& path;
  std::size_t at = 0;
  void need(std::size_t n) {
    if (bytes.size() - at < n) throw std::runtime_error(path + ": the checkpoint is truncated");
  }
  template <class T>
  T value() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> array() {
    std::uint64_t n = value<std::uint64_t>();
    if (n > (bytes.size() - at) / sizeof(T)) throw std::runtime_error(path + ": the checkpoint is truncated");
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));  // an empty vector's data() may be null
    at += n * sizeof(T);
    return v;
  }
  std::string text() {
    std::vector<char> v = array<char>();
    return std::string(v.begin(), v.end());
  }
};

void write_accumulator(Writer& w, const std::optional<Accumulator>& a) {
  w.value(std::uint8_t(a.has_value()));
  if (!a) return;
  w.value(std::int32_t(a->width));
  w.value(std::int32_t(a->height));
  w.value(a->samples_per_pixel);
  w.array(a->sum);
  w.array(a->raw_sum);
}

std::optional<Accumulator> read_accumulator(Reader& r) {
  if (!r.value<std::uint8_t>()) return std::nullopt;
  Accumulator a;
  a.width = r.value<std::int32_t>();
  a.height = r.value<std::int32_t>();
  a.samples_per_pixel = r.value<std::uint64_t>();
  a.sum = r.array<double>();
  a.raw_sum = r.array<double>();
  if (a.width <= 0 || a.height <= 0 || a.sum.size() != std::size_t(a.width) * a.height * 3 ||
      (!a.raw_sum.empty() && a.raw_sum.size() != a.sum.size()))
    throw std::runtime_error(r.path + ": the checkpoint's image sizes are inconsistent");
  return a;
}

void write_batch_means(Writer& w, const BatchMeansErrorEstimate::State* e) {
  w.value(std::uint8_t(e != nullptr));
  if (!e) return;
  w.value(std::int32_t(e->width));
  w.value(std::int32_t(e->height));
  w.value(e->rounds);
  w.array(e->start_sums);
  w.value(std::uint32_t(e->levels.size()));
  for (const BatchMeansErrorEstimate::Level& l : e->levels) {
    w.value(l.batch_rounds);
    w.value(l.batches);
    w.value(l.closed_rounds);
    w.value(l.open_round);
    w.array(l.open_sums);
    w.array(l.sum_sq_over_n);
  }
}

std::optional<BatchMeansErrorEstimate::State> read_batch_means(Reader& r) {
  if (!r.value<std::uint8_t>()) return std::nullopt;
  BatchMeansErrorEstimate::State e;
  e.width = r.value<std::int32_t>();
  e.height = r.value<std::int32_t>();
  e.rounds = r.value<std::uint64_t>();
  e.start_sums = r.array<double>();
  const std::uint32_t levels = r.value<std::uint32_t>();
  if (levels > 64) throw std::runtime_error(r.path + ": the checkpoint's batch statistics are inconsistent");
  for (std::uint32_t j = 0; j < levels; ++j) {
    BatchMeansErrorEstimate::Level l;
    l.batch_rounds = r.value<std::uint64_t>();
    l.batches = r.value<std::uint64_t>();
    l.closed_rounds = r.value<std::uint64_t>();
    l.open_round = r.value<std::uint64_t>();
    l.open_sums = r.array<double>();
    l.sum_sq_over_n = r.array<double>();
    e.levels.push_back(std::move(l));
  }
  return e;
}

// Format 04: a count, then each layer's statistics (PT's, RB's, and the check of RB's layer against
// PT's estimate of its share: image/error_estimate.h; then, under --rb-level consistent, PT's u and d
// in batches of a round: render/render_job.cpp); before, one optional estimate.
void write_error_estimate(Writer& w, const std::vector<BatchMeansErrorEstimate::State>& layers) {
  w.value(std::uint8_t(layers.size()));
  for (const BatchMeansErrorEstimate::State& e : layers) write_batch_means(w, &e);
}

std::vector<BatchMeansErrorEstimate::State> read_error_estimate(Reader& r, bool one_optional) {
  std::vector<BatchMeansErrorEstimate::State> layers;
  const std::uint8_t count = one_optional ? 1 : r.value<std::uint8_t>();
  if (count > 5) throw std::runtime_error(r.path + ": the checkpoint's batch statistics are inconsistent");
  for (std::uint8_t l = 0; l < count; ++l) {
    std::optional<BatchMeansErrorEstimate::State> e = read_batch_means(r);
    if (e) layers.push_back(std::move(*e));
    else if (!one_optional) throw std::runtime_error(r.path + ": the checkpoint's batch statistics are inconsistent");
  }
  return layers;
}

void write_rb_level(Writer& w, const std::optional<RbLevel::State>& level) {
  write_batch_means(w, level ? &level->pt : nullptr);
  write_batch_means(w, level ? &level->rb : nullptr);
}

std::optional<RbLevel::State> read_rb_level(Reader& r) {
  std::optional<BatchMeansErrorEstimate::State> pt = read_batch_means(r), rb = read_batch_means(r);
  if (pt.has_value() != rb.has_value()) throw std::runtime_error(r.path + ": the checkpoint's RB level is inconsistent");
  if (!pt) return std::nullopt;
  return RbLevel::State{std::move(*pt), std::move(*rb)};
}

void write_regional_error(Writer& w, const std::optional<RegionalError::State>& regional) {
  write_error_estimate(w, regional ? regional->layers : std::vector<BatchMeansErrorEstimate::State>{});
}

std::optional<RegionalError::State> read_regional_error(Reader& r) {
  const std::uint8_t count = r.value<std::uint8_t>();
  if (count == 0) return std::nullopt;
  if (count > 4) throw std::runtime_error(r.path + ": the checkpoint's regional error is inconsistent");
  RegionalError::State s;
  for (std::uint8_t l = 0; l < count; ++l) {
    std::optional<BatchMeansErrorEstimate::State> e = read_batch_means(r);
    if (!e) throw std::runtime_error(r.path + ": the checkpoint's regional error is inconsistent");
    s.layers.push_back(std::move(*e));
  }
  return s;
}

// Format 06: the check of RB's layer (ImageErrorEstimate::RbBiasSums).
void write_rb_bias_sums(Writer& w, const ImageErrorEstimate::RbBiasSums& t) {
  for (double v : {t.e, t.e_sq, t.a, t.a_e, t.a_sq}) w.value(v);
  w.value(t.batches);
}

ImageErrorEstimate::RbBiasSums read_rb_bias_sums(Reader& r) {
  ImageErrorEstimate::RbBiasSums t;
  for (double* v : {&t.e, &t.e_sq, &t.a, &t.a_e, &t.a_sq}) *v = r.value<double>();
  t.batches = r.value<std::uint64_t>();
  return t;
}

}  // namespace

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  Writer w;
  w.bytes.append(kMagic, sizeof kMagic);
  w.text(c.options);
  w.value(c.rounds);
  w.value(c.render_seconds);
  write_accumulator(w, c.pt);
  write_accumulator(w, c.rb);
  w.value(std::uint8_t(c.rb_state.has_value()));
  if (c.rb_state) {
    w.array(c.rb_state->e_in);
    w.value(c.rb_state->eye_rounds);
    w.value(std::uint8_t(c.rb_state->warmed_up));
  }
  write_error_estimate(w, c.error_estimate);
  write_rb_level(w, c.rb_level);
  write_regional_error(w, c.regional_error);
  write_rb_bias_sums(w, c.rb_bias_sums);
  if (!c.further_views.empty()) {
    w.bytes.append(kViewsTag, sizeof kViewsTag);
    w.value(std::uint64_t(c.further_views.size()));
    for (const Checkpoint::View& view : c.further_views) {
      write_accumulator(w, view.pt);
      write_accumulator(w, view.rb);
      write_error_estimate(w, view.error_estimate);
      write_rb_level(w, view.rb_level);
      write_regional_error(w, view.regional_error);
      write_rb_bias_sums(w, view.rb_bias_sums);
    }
  }
  write_file_atomically(path, "checkpoint", [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(w.bytes.data(), std::streamsize(w.bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + tmp);
  });
}

Checkpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read the checkpoint (missing or unreadable)");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto starts_with = [&](const char (&magic)[8]) {
    return bytes.size() >= sizeof magic && std::memcmp(bytes.data(), magic, sizeof magic) == 0;
  };
  const bool v1 = starts_with(kMagicV1), v2 = starts_with(kMagicV2), v3 = starts_with(kMagicV3),
             v4 = starts_with(kMagicV4), v5 = starts_with(kMagicV5);
  if (!v1 && !v2 && !v3 && !v4 && !v5 && !starts_with(kMagic))
    throw std::runtime_error(path + ": not a bundlepath checkpoint");
  Reader r{bytes, path, sizeof kMagic};
  Checkpoint c;
  c.options = r.text();
  c.rounds = r.value<std::uint64_t>();
  c.render_seconds = r.value<double>();
  c.pt = read_accumulator(r);
  c.rb = read_accumulator(r);
  if (r.value<std::uint8_t>()) {
    RayBundlePass::State s;
    s.e_in = r.array<cl_float4>();
    s.eye_rounds = r.value<std::uint64_t>();
    s.warmed_up = r.value<std::uint8_t>() != 0;
    c.rb_state = s;
  }
  if (!v1) c.error_estimate = read_error_estimate(r, v2 || v3);
  if (!v1 && !v2) c.rb_level = read_rb_level(r);
  if (!v1 && !v2 && !v3 && !v4) c.regional_error = read_regional_error(r);
  const bool has_rb_bias_sums = !v1 && !v2 && !v3 && !v4 && !v5;
  if (has_rb_bias_sums) c.rb_bias_sums = read_rb_bias_sums(r);
  if (!v1 && !v2 && bytes.size() - r.at >= sizeof kViewsTag &&
      std::memcmp(bytes.data() + r.at, kViewsTag, sizeof kViewsTag) == 0) {
    r.at += sizeof kViewsTag;
    const std::uint64_t views = r.value<std::uint64_t>();
    for (std::uint64_t k = 0; k < views; ++k) {
      Checkpoint::View view;
      view.pt = read_accumulator(r);
      view.rb = read_accumulator(r);
      view.error_estimate = read_error_estimate(r, v3);
      view.rb_level = read_rb_level(r);
      if (!v3 && !v4) view.regional_error = read_regional_error(r);
      if (has_rb_bias_sums) view.rb_bias_sums = read_rb_bias_sums(r);
      c.further_views.push_back(std::move(view));
    }
  }
  if (r.at != bytes.size()) throw std::runtime_error(path + ": the checkpoint has trailing bytes");
  return c;
}

}  // namespace bp
