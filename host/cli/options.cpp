#include "cli/options.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>

namespace bp {
namespace {

template <class T>
T parse_number(const std::string& option, const std::string& text, T min_value, T max_value, const char* what) {
  T value{};
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  bool ok = ec == std::errc() && ptr == end;
  if constexpr (std::is_floating_point_v<T>) ok = ok && std::isfinite(value);
  if (!ok || value < min_value || value > max_value)
    throw UsageError(option + ": expected " + what + ", got '" + text + "'");
  return value;
}

// --environment's argument is a map file (not R,G,B) when it ends in .exr or names a file.
bool names_environment_file(const std::string& v) {
  const std::string ext = v.size() >= 4 ? v.substr(v.size() - 4) : "";
  const bool exr = ext.size() == 4 && ext[0] == '.' && std::tolower(ext[1]) == 'e' && std::tolower(ext[2]) == 'x' &&
                   std::tolower(ext[3]) == 'r';
  std::error_code ignored;
  return exr || std::filesystem::is_regular_file(v, ignored);
}

}  // namespace

const char* main_help() {
  return R"(bundlepath - global illumination on any OpenCL device

usage:
  bundlepath render SCENE.gltf|SCENE.glb [options]   render an image (see `bundlepath render --help`)
  bundlepath devices                                 list OpenCL platforms and devices with their index
  bundlepath compare IMAGE.exr REFERENCE.exr         relMSE, RMSE and bias of IMAGE against REFERENCE
             [--layer NAME] [--json]
  bundlepath --help | --version

exit codes: 0 done; 1 device or I/O failure; 2 bad command line or no OpenCL platform;
            3 the scene file cannot be used; 130 interrupted (the samples done so far were written)
)";
}

const char* render_help() {
  return R"(usage: bundlepath render SCENE [options]

Renders SCENE (glTF 2.0: .gltf or .glb) and writes PREFIX.exr (linear float32) and PREFIX.png
(tone-mapped sRGB). Ctrl-C stops after the current batch and writes what is done (exit 130).
Under `mpirun -np N` (a build with MPI) the N ranks render one image: each its share of every
batch, rank 0 sums them and alone writes the files (README, "Several ranks: MPI").

options (defaults in brackets):
  --out PREFIX        output path without extension            [out/<scene name>]
  --width W           image width in pixels, 1..16384          [512]
  --height H          image height in pixels, 1..16384         [width / camera aspect ratio]
  --spp N             samples per pixel (pt, combined)         [pt: 64, unless --time is given]
  --iterations N      ray-bundle iterations (rb, combined)     [rb: 1000, unless --time is given]
                      combined: give --spp, --iterations or --time; the other count follows
                      from --ratio   [combined: as long as 64 PT spp alone take (auto), else 64 spp]
  --time SECONDS      stop after this much rendering time; with --spp, whichever comes first.
                      A render stops between batches, at the batch end nearest SECONDS
  --target-error X    render until the estimated relMSE (below) is at most X, a number > 0;
                      with --time as a cap, whichever comes first; not with --spp or
                      --iterations. Checked after each batch once the estimate has 7
                      degrees of freedom (8 batches of one estimator); the progress
                      bar's ETA is the time to X from the estimate's 1/t decay
  --error-batch N     RB iterations per batch of the error estimate (rb, combined)  [64]
  --error-levels L    also estimate from batches 2, 4, ... 2^(L-1) times longer, into --stats
                      (the check that the batches outlast RB's correlation)   [1]
  --seed K            random seed; same seed, same device -> bit-identical image   [1]
  --device SPEC       device index or name substring (see `bundlepath devices`), or several,
                      comma-separated, or all: combined runs RB on the first and PT on the
                      others at the same time; pt splits its samples over all  [first GPU, else CPU]
  --mode MODE         pt (path tracing), rb (global ray-bundle iteration), or combined
                      (both, weighted per path so the sum stays unbiased; with
                      --ratio auto, the path tracer alone where RB cannot pay)  [combined]
  --weights W         combined: product (exact per-vertex weights), paper (the paper's
                      eq. 9/10 weights, one P per patch), none (plain sum: double counts)  [product]
  --beta B            product weights: the per-vertex factor of w_RB = prod beta, from PT's
                      density P of the vertex's direction: clamped, min(1, N2/(N1 P)), or
                      balance, N2/(N2 + N1 P) (the paper's one-step weight)  [clamped]
  --rb-level L        product weights: the level (mean over the pixels, per channel) of RB's
                      share of the image: corrected (RB's layer scaled to the inverse-variance
                      mean of its own level and PT's estimate of the same share, PT's
                      unweighted less weighted image: removes RB's level noise, a ratio
                      estimator, consistent) or own (the plain weighted sum)   [corrected]
  --rb-light-rate R   combined with light sampling: the probability that a patch traces its
                      shadow ray in an iteration, in (0, 1] (the weights count R·N2 samples)
                                                                [min(1, pixels / patches)]
  --rb-sun S          combined with light sampling: how RB's patches sample directional lights:
                      chosen (only when their light sample chooses the sun, like any other
                      light) or own (every patch that takes its light sample also takes one
                      of each sun, every iteration: the weights then give RB more of the
                      sun's light after the eye vertex, and PT less)            [chosen]
  --eye-direct E      combined with light sampling: the eye vertex's direct light split with
                      RB by the four techniques (shared; RB's share from a view-independent
                      proxy of PT's density: smooth, but blurred to RB's patches), PT's alone
                      (pt: unbiased per pixel, noisy at few samples), or auto: shared when
                      the render gives each pixel fewer than 96 PT samples (from --spp,
                      --iterations and --ratio, or for --time from the ratio probe's costs;
                      under --ratio auto, at the c it picks where the light is PT's alone;
                      --resume reuses the saved choice)                       [auto]
  --ratio C           combined: PT samples per pixel per RB iteration, or auto   [auto]
                      0: ray bundles alone (w_RB = 1; count with --iterations or --time)
                      auto: a short timed probe after the kernels are built (about 2 % of
                      --time, or of the estimated time of --spp / --iterations, at most
                      1.5 s, and at least one RB iteration; not counted in --time, its
                      samples are discarded) measures PT's cost per sample (on the same view
                      at about 128x128 pixels, scaled) and RB's per iteration, and picks c,
                      a power of 2, so that PT gets about 12 % of the time (65 % where
                      the eye vertex's direct light is PT's alone: --eye-direct pt, or auto
                      resolved to pt), and a round (N1 PT samples + N2 RB iterations) that
                      fits in --time. Where one RB iteration costs more than a PT sample of
                      the whole image (many more patches than pixels) it picks the path
                      tracer alone (c = inf, printed; "inf" in --stats), unless --iterations
                      is given (then PT gets at least 98 % of the time). --spp or --iterations
                      then fixes the other count from that c. The chosen c is printed and in
                      --stats; give it as --ratio for a reproducible image (inf: --mode pt).
                      --resume reuses the saved c
  --no-light-sampling turn light sampling off: emitters are then reached by BSDF sampling (pt)
                      and bundles (rb) only, as in the paper. Light sampling (next-event
                      estimation in PT, a shadow ray per patch in RB) acts in --mode pt and in
                      --mode combined with product weights; --mode rb and --weights paper/none
                      never sample lights. Point, spot and directional lights
                      (KHR_lights_punctual) are reached by light sampling only
  --light-selection S light sampling: how a light is chosen for a receiving patch: tree (a
                      BVH over the lights bounding power, position and orientation; nearby,
                      facing lights are chosen more often; suns and the environment by power,
                      less often where the patch's 16 test rays do not reach them) or power (by
                      power alone, the same for every receiver)                   [tree]
  --kernels K         specialised (built with only the features the scene and options use:
                      Phong lobe, light sampling) or generic (everything)  [specialised]
  --layers all        also write the unweighted pt_raw and rb_raw layers
  --reference REF.exr report relMSE, RMSE and mean bias of every layer against REF
  --contact-sheet F   write F.png: non-weighted PT, weighted PT, combined, non-weighted RB,
                      weighted RB, reference (implies --layers all)
  --patch-size M      target patch edge in metres              [scene diagonal / 20]
  --bins R            transillumination buffer R x R bins (rb) [an average patch covers 4 bins]
  --warmup N          ray-bundle iterations before the image starts (rb)  [16]
  --rb-directions D   rb: the iterations' directions: independent (each drawn on its own, as in
                      the paper) or stratified (experimental: blocks of 64 iterations, four
                      interleaved sequences that each visit the 16 cells of the direction square
                      once; less level noise in short renders, but light paths of more than
                      four bundle segments are biased, about -1 % on the house)  [independent]
  --contact-depth F   rb: surfaces closer than F times the scene's bounding diameter along a
                      bundle direction touch: they exchange nothing, and a patch's incoming
                      light is the mean over its uncovered part; 0 turns it off   [0.001]
  --environment R,G,B uniform environment radiance (W sr^-1 m^-2, linear RGB) that every ray
                      leaving the scene sees: the background, and light from every open
                      direction (PT: by BSDF sampling and light sampling; RB: where no patch is
                      in front, and its patches' light samples)  [0,0,0]
  --environment FILE.exr  the same from an equirectangular RGB(A) EXR (any argument ending in .exr
                      or naming a file): +Y up, the image's centre column looking along -Z,
                      nearest-texel lookup, light sampling by luminance x sin(theta); at most
                      8192x4096 texels, finite and >= 0 (else exit 3)
  --rb-shading S      eye estimate: gouraud (interpolated across patches) or flat  [gouraud]
  --rb-eye-gather G   eye estimate of Lambert eye vertices: blocks (once per 16 iterations
                      from per-patch sums, the same image to float rounding) or every
                      (every pixel every iteration, for comparison; also what
                      --weights paper does)   [blocks]
  --stats FILE        write run statistics as JSON, with "estimated_rel_mse": the image's
                      relMSE estimated without a reference from the spread of batch means
                      (PT: batches of its rounds; RB: of --error-batch iterations, longer
                      than its chain's correlation; combined: each layer from its own,
                      their variances summed); the EXR
                      gets a 'stderr' layer, each pixel's standard error. It sees noise
                      only: RB's discretisation (patches, bins, Gouraud) is a bias no
                      variance shows (rb, and its share of combined): about 0.0004
                      relMSE on the Cornell box, 0.026 on the glossy one (README)
  --checkpoint FILE   save the render's state to FILE every --checkpoint-every seconds [60]
                      and when it ends or is interrupted
  --resume FILE       continue the render saved in FILE (same scene and options). --spp and
                      --iterations are totals, so the result equals an uninterrupted render;
                      --time counts this run only
  --camera C          the camera node to render from: its index among the scene's camera nodes
                      (depth-first, from 0) or its node's (else camera's) name   [0]
  --cameras all       a walkthrough of every camera node at its rest pose, in scene order
  --camera-path FILE  a walkthrough along FILE.json: [{"position": [x,y,z], "target": [x,y,z],
                      "up": [x,y,z] (default [0,1,0]), "yfov": radians (default the scene's)}, ...]
  --camera-animation  a walkthrough of --camera's glTF animation (translation and rotation
                      channels, LINEAR or STEP), sampled at --fps from its first keyframe to
                      its last; --cameras all renders animated cameras at their rest pose
  --fps F             frames per second of --camera-animation and --video    [24]
  --video FILE.mp4    also encode a walkthrough's PNGs with ffmpeg (must be on PATH)
                      A walkthrough writes PREFIX_0000.exr/.png, PREFIX_0001... from one
                      ray-bundle chain shared by all its views (each view its own eye gather
                      and PT samples); --spp/--iterations/--time count the whole walk;
                      checkpoints hold every view. One device; not with --reference or
                      --contact-sheet
  --exposure STOPS    exposure of the PNG                      [0]
  --max-depth N       safety cap on path length                [65536]
  -h, --help          this text
)";
}

RenderOptions parse_render_options(const std::vector<std::string>& args) {
  RenderOptions o;
  bool spp_given = false, iterations_given = false;
  using Setter = std::function<void(const std::string& option, const std::string& value)>;
  const std::map<std::string, Setter> setters = {
      {"--out", [&](auto&, auto& v) { o.out_prefix = v; }},
      {"--width", [&](auto& k, auto& v) { o.width = parse_number<int>(k, v, 1, 16384, "an integer in 1..16384"); }},
      {"--height", [&](auto& k, auto& v) { o.height = parse_number<int>(k, v, 1, 16384, "an integer in 1..16384"); }},
      {"--spp", [&](auto& k, auto& v) {
         o.spp = parse_number<std::uint64_t>(k, v, 1, 1ull << 32, "a positive integer");
         spp_given = true;
       }},
      {"--iterations", [&](auto& k, auto& v) {
         o.iterations = parse_number<std::uint64_t>(k, v, 1, 1ull << 32, "a positive integer");
         iterations_given = true;
       }},
      {"--bins", [&](auto& k, auto& v) { o.bins = parse_number<std::uint32_t>(k, v, 1, 16384, "an integer in 1..16384"); }},
      {"--contact-depth", [&](auto& k, auto& v) {
         o.contact_depth = parse_number<float>(k, v, 0.0f, 0.1f, "a fraction of the scene's diameter in [0, 0.1]");
       }},
      {"--rb-directions", [&](auto& k, auto& v) {
         if (v != "stratified" && v != "independent")
           throw UsageError(k + ": expected stratified or independent, got '" + v + "'");
         o.rb_directions = v;
       }},
      {"--warmup", [&](auto& k, auto& v) {
         o.warmup = parse_number<std::uint32_t>(k, v, 0, 1u << 20, "an integer in 0..1048576");
       }},
      {"--environment", [&](auto& k, auto& v) {
         if (names_environment_file(v)) {
           o.environment_path = v;
           return;
         }
         std::array<float, 3> rgb{};
         std::size_t start = 0;
         for (int c = 0; c < 3; ++c) {
           const std::size_t comma = v.find(',', start);
           if ((c < 2) != (comma != std::string::npos))
             throw UsageError(k + ": expected R,G,B (three radiances >= 0), got '" + v + "'");
           rgb[c] = parse_number<float>(k, v.substr(start, comma - start), 0.0f, 1e30f, "R,G,B (three radiances >= 0)");
           start = comma + 1;
         }
         o.environment = rgb;
       }},
      {"--rb-eye-gather", [&](auto& k, auto& v) {
         if (v != "blocks" && v != "every") throw UsageError(k + ": expected blocks or every, got '" + v + "'");
         o.eye_blocks = v == "blocks";
       }},
      {"--rb-shading", [&](auto& k, auto& v) {
         if (v != "gouraud" && v != "flat") throw UsageError(k + ": expected gouraud or flat, got '" + v + "'");
         o.gouraud = v == "gouraud";
       }},
      {"--weights", [&](auto& k, auto& v) {
         if (v != "product" && v != "paper" && v != "none")
           throw UsageError(k + ": unknown weights '" + v + "' (available: product, paper, none)");
         o.weights = v;
       }},
      {"--rb-level", [&](auto& k, auto& v) {
         if (v != "corrected" && v != "own") throw UsageError(k + ": expected corrected or own, got '" + v + "'");
         o.rb_level = v;
       }},
      {"--beta", [&](auto& k, auto& v) {
         if (v != "clamped" && v != "balance")
           throw UsageError(k + ": unknown beta '" + v + "' (available: clamped, balance)");
         o.beta = v;
       }},
      {"--eye-direct", [&](auto& k, auto& v) {
         if (v != "shared" && v != "pt" && v != "auto")
           throw UsageError(k + ": expected shared, pt or auto, got '" + v + "'");
         o.eye_direct = v;
       }},
      {"--rb-sun", [&](auto& k, auto& v) {
         if (v != "own" && v != "chosen") throw UsageError(k + ": expected own or chosen, got '" + v + "'");
         o.rb_sun_own = v == "own";
       }},
      {"--rb-light-rate", [&](auto& k, auto& v) {
         o.light_rate = parse_number<float>(k, v, 1e-6f, 1.0f, "a probability in (0, 1]");
       }},
      {"--ratio", [&](auto& k, auto& v) {
         if (v == "auto") {
           o.ratio = -1.0;
           return;
         }
         std::string text = v;
         double value;
         if (auto slash = text.find('/'); slash != std::string::npos)  // "1/16"
           value = parse_number<double>(k, text.substr(0, slash), 0.0, 1e9, "auto or a ratio like 0.25 or 1/4") /
                   parse_number<double>(k, text.substr(slash + 1), 1e-9, 1e9, "auto or a ratio like 0.25 or 1/4");
         else
           value = parse_number<double>(k, text, 0.0, 1e9, "auto or a ratio like 0.25 or 1/4");
         if (value != 0.0 && (value < 1e-6 || value > 1e6))
           throw UsageError(k + ": expected 0 or a ratio in [1e-6, 1e6], got '" + v + "'");
         o.ratio = value;
       }},
      {"--light-selection", [&](auto& k, auto& v) {
         if (v != "tree" && v != "power")
           throw UsageError(k + ": unknown light selection '" + v + "' (available: tree, power)");
         o.light_selection = v;
       }},
      {"--kernels", [&](auto& k, auto& v) {
         if (v != "specialised" && v != "generic")
           throw UsageError(k + ": expected specialised or generic, got '" + v + "'");
         o.generic_kernels = v == "generic";
       }},
      {"--layers", [&](auto& k, auto& v) {
         if (v != "all") throw UsageError(k + ": the only value is 'all'");
         o.all_layers = true;
       }},
      {"--reference", [&](auto&, auto& v) { o.reference_path = v; }},
      {"--contact-sheet", [&](auto&, auto& v) {
         o.contact_sheet_path = v;
         o.all_layers = true;
       }},
      {"--checkpoint", [&](auto&, auto& v) { o.checkpoint_path = v; }},
      {"--checkpoint-every", [&](auto& k, auto& v) {
         o.checkpoint_every = parse_number<double>(k, v, 0.0, 1e7, "seconds >= 0");
       }},
      {"--resume", [&](auto&, auto& v) { o.resume_path = v; }},
      {"--time", [&](auto& k, auto& v) { o.seconds = parse_number<double>(k, v, 1e-3, 1e7, "seconds > 0"); }},
      {"--target-error", [&](auto& k, auto& v) {
         o.target_error = parse_number<double>(k, v, 1e-300, 1e300, "a relMSE > 0 (e.g. 0.001)");
       }},
      {"--error-batch", [&](auto& k, auto& v) {
         o.error_batch = parse_number<std::uint64_t>(k, v, 1, 1ull << 24, "an integer in 1..16777216");
       }},
      {"--error-levels", [&](auto& k, auto& v) { o.error_levels = parse_number<int>(k, v, 1, 12, "an integer in 1..12"); }},
      {"--seed", [&](auto& k, auto& v) {
         o.seed = parse_number<std::uint32_t>(k, v, 0, 0xffffffffu, "an integer in 0..4294967295");
       }},
      {"--device", [&](auto&, auto& v) { o.device = v; }},
      {"--mode", [&](auto& k, auto& v) {
         if (v != "pt" && v != "rb" && v != "combined")
           throw UsageError(k + ": unknown mode '" + v + "' (available: pt, rb, combined)");
         o.mode = v;
       }},
      {"--patch-size", [&](auto& k, auto& v) {
         o.patch_size = parse_number<float>(k, v, 1e-9f, 1e9f, "a length in metres > 0");
       }},
      {"--stats", [&](auto&, auto& v) { o.stats_path = v; }},
      {"--camera", [&](auto& k, auto& v) {
         if (v.empty()) throw UsageError(k + ": expected a camera node's index or name");
         o.views.camera = v;
       }},
      {"--cameras", [&](auto& k, auto& v) {
         if (v != "all") throw UsageError(k + ": the only value is 'all'");
         o.views.all_cameras = true;
       }},
      {"--camera-path", [&](auto& k, auto& v) {
         if (v.empty()) throw UsageError(k + ": expected a file name");
         o.views.path_file = v;
       }},
      {"--fps", [&](auto& k, auto& v) { o.views.fps = parse_number<double>(k, v, 1e-3, 1e4, "frames per second > 0"); }},
      {"--video", [&](auto& k, auto& v) {
         if (v.empty()) throw UsageError(k + ": expected a file name");
         o.video_path = v;
       }},
      {"--exposure", [&](auto& k, auto& v) { o.exposure = parse_number<float>(k, v, -64.0f, 64.0f, "stops in -64..64"); }},
      {"--max-depth", [&](auto& k, auto& v) {
         o.max_depth = parse_number<std::uint32_t>(k, v, 1, 1u << 24, "an integer in 1..16777216");
       }},
  };
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string arg = args[i];
    if (arg == "--no-light-sampling") {  // the flags without a value
      o.light_sampling = false;
    } else if (arg == "--camera-animation") {
      o.views.animation = true;
    } else if (arg.rfind("--", 0) == 0) {
      std::string value;
      bool has_value = false;
      if (auto eq = arg.find('='); eq != std::string::npos) {
        value = arg.substr(eq + 1);
        arg = arg.substr(0, eq);
        has_value = true;
      }
      auto it = setters.find(arg);
      if (it == setters.end()) throw UsageError("unknown option '" + arg + "' (see `bundlepath render --help`)");
      if (!has_value) {
        if (i + 1 >= args.size()) throw UsageError(arg + ": missing value");
        value = args[++i];
      }
      it->second(arg, value);
    } else if (arg.size() > 1 && arg[0] == '-') {
      throw UsageError("unknown option '" + arg + "' (see `bundlepath render --help`)");
    } else if (o.scene.empty()) {
      o.scene = arg;
    } else {
      throw UsageError("unexpected argument '" + arg + "': only one scene file is rendered at a time");
    }
  }
  if (o.scene.empty()) throw UsageError("no scene file given (usage: bundlepath render SCENE.gltf [options])");
  if (spp_given && o.mode == "rb") throw UsageError("--spp counts path-tracer samples; with --mode rb use --iterations");
  if (iterations_given && o.mode == "pt") throw UsageError("--iterations counts ray-bundle iterations; with --mode pt use --spp");
  if (spp_given && iterations_given)
    throw UsageError("give --spp or --iterations, not both: --ratio fixes one from the other");
  if (o.target_error > 0.0 && (spp_given || iterations_given))
    throw UsageError(std::string("--target-error ends the render by its error: not with ") +
                     (spp_given ? "--spp" : "--iterations") + " (use --time as a cap)");
  const bool unbounded = o.seconds == 0.0 && o.target_error == 0.0;
  if (o.mode == "pt" && !spp_given && unbounded) o.spp = 64;
  if (o.mode == "rb" && !iterations_given && unbounded) o.iterations = 1000;
  if (o.mode == "combined" && o.ratio == 0.0 && spp_given)
    throw UsageError("--ratio 0 runs ray bundles alone, no path-tracer samples: count with --iterations or --time, not --spp");
  if (o.mode == "combined" && !spp_given && !iterations_given && unbounded) {
    if (o.ratio == 0.0) o.iterations = 1000;  // ray bundles alone: --mode rb's default
    else if (o.ratio < 0.0) o.equal_time_spp = 64;  // auto: the time --mode pt's default takes
    else o.spp = 64;
  }
  if (o.out_prefix.empty()) o.out_prefix = (std::filesystem::path("out") / std::filesystem::path(o.scene).stem()).string();
  return o;
}

}  // namespace bp
