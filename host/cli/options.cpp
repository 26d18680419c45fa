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
  bundlepath render SCENE.gltf|SCENE.glb [options]   render an image (`bundlepath render --help`,
                                                     every option: `bundlepath render --help-all`)
  bundlepath devices                                 list OpenCL platforms and devices with their index
  bundlepath compare IMAGE.exr REFERENCE.exr         relMSE, RMSE and bias of IMAGE against REFERENCE
             [--layer NAME] [--json]
  bundlepath --help | --version

exit codes:
  0    done
  1    a device or ffmpeg failed, a file could not be read or written, or no device matches --device
  2    a bad command line, a run too large for the device, or a missing OpenCL driver, ffmpeg,
       OpenImageDenoise or MPI
  3    the scene, its environment map or its camera path cannot be used
  130  interrupted: the samples done so far were written
every message and what to do: docs/guide.md, "Troubleshooting"
)";
}

namespace {

// `render --help` is the head and the everyday options; `--help-all` adds the estimator's tuning
// knobs. docs/guide.md lists every option again (tests/e2e/test_docs.cpp keeps them in step).
constexpr const char* kRenderHelpHead = R"(usage: bundlepath render SCENE [options]

Renders SCENE (glTF 2.0: .gltf or .glb) to PREFIX.exr (linear float32) and PREFIX.png (sRGB).
Ctrl-C stops after the current batch and writes what is done (exit 130). Under `mpirun -np N`
the N ranks render one image. The user guide: docs/guide.md. Defaults in brackets.

options:
  --out PREFIX        output path without extension                  [out/<scene name>]
  --width W           image width in pixels, 1..16384                [512]
  --height H          image height in pixels, 1..16384               [width / camera aspect]
  --spp N             path-tracer samples per pixel (pt, combined)   [pt: 64]
  --iterations N      ray-bundle iterations (rb, combined; combined: give --spp or
                      --iterations, and --ratio fixes the other)                  [rb: 1000]
  --time SECONDS      stop at the batch end nearest this much rendering time; with a count,
                      whichever comes first [combined, no budget: as long as pt's 64 spp take]
  --target-error X    render until the estimated relMSE is at most X (e.g. 0.001); --time
                      caps it; not with --spp or --iterations
  --target-block-error E  render until the worst region of the --regions grid is expected to be
                      off by at most E (a relative error, e.g. 0.02); like --target-error
  --mode MODE         pt (path tracing), rb (global ray-bundle iteration) or combined (both,
                      weighted per path; RB's share corrected by PT's so it converges) [combined]
  --ratio C           combined: PT samples per pixel per RB iteration (1/16, 4; 0: RB alone),
                      or auto: timed on the scene and device (more PT where it is glossy),
                      the choice printed                                              [auto]
  --device SPEC       index or name substring (see `bundlepath devices`), a comma-separated list
                      (combined: RB on the first, PT on the others), or all  [first GPU, else CPU]
  --seed K            random seed: same seed, device and options, the same image bit for bit [1]
  --reference REF.exr report relMSE, RMSE and mean bias of every layer against REF
  --stats FILE        write run statistics as JSON, with the estimated relMSE (the noise, and
                      the ray bundles' bias where the path tracer sees it)
  --checkpoint FILE   save the render's state to FILE every --checkpoint-every seconds and at
                      the end or on Ctrl-C
  --resume FILE       continue the render saved in FILE (same scene and options); --spp and
                      --iterations are totals, --time counts this run
  --verbose           print the OpenCL compiler's messages when kernels are built from source
  -h, --help          this text
  --help-all          every option, with the estimator's tuning knobs

outputs:
  --denoise           denoise the image with OpenImageDenoise (colour + albedo + normal, as
                      Blender does), inside --time; the EXR keeps the render's own as raw.*,
                      the PNG is the denoised one; --ratio auto then takes the path tracer
                      alone. Needs `bash scripts/setup.sh --oidn`
  --layers all        also write the unweighted pt_raw and rb_raw layers
  --contact-sheet F   write F.png: unweighted PT, weighted PT, combined, unweighted RB,
                      weighted RB, reference (implies --layers all)
  --exposure STOPS    exposure of the PNG                                          [0]
  --save-every S      also write the image files (EXR and PNG, the same layers) every S seconds
                      while rendering, to watch it converge or stop early; with --denoise
                      denoised too where that takes under a tenth of S               [off]
  --checkpoint-every S  seconds between the saves of --checkpoint                 [60]
  --regions N         the N x N grid of the regional error estimate (--stats' regional_error,
                      the EXR's region_error layer) and of --rb-level regional      [8]

scene and light:
  --environment R,G,B uniform environment radiance (W sr^-1 m^-2, linear RGB) around the
                      scene: the background, and light from every open direction  [0,0,0]
  --environment FILE.exr  the same from an equirectangular RGB(A) EXR: +Y up, the centre
                      column along -Z; at most 8192x4096 texels, finite and >= 0 (else exit 3)
  --patch-size M      ray bundles' target patch edge in metres      [scene diagonal / 20]
  --patch-clusters on|off  on: the ray bundles see flat neighbouring triangles of one plain
                      material merged into convex patches (at most --patch-size across, else
                      the scene diagonal / 80), so a finely tessellated scene costs what its
                      surfaces need, not its triangle count                          [on]
  --patch-refine on|off  on: patches that a sharp shadow's edge crosses (a point, spot or sun
                      light's, or a small emitter's; seen by shadow rays from their corners)
                      are split up to twice, halving their edges, until the patch count has
                      doubled (or reached --patches)                                 [on]
  --patches N         the most patches --patch-refine may bring the layout to; below what
                      clusters and --patch-size give, nothing is split (a larger --patch-size
                      coarsens)                                      [twice the unrefined count]
  --no-light-sampling turn light sampling off (then point, spot and directional lights stay
                      dark, and emitters are found by BSDF sampling and bundles alone)

walkthroughs (frames PREFIX_0000.exr/.png, PREFIX_0001...; one device, one process):
  --camera C          one camera node: its index among the scene's camera nodes (depth-first,
                      from 0) or its node's (else camera's) name                   [0]
  --cameras all       a walkthrough of every camera node at its rest pose, in scene order
  --camera-path FILE  a walkthrough along FILE.json: [{"position": [x,y,z], "target": [x,y,z],
                      "up": [x,y,z] (default [0,1,0]), "yfov": radians}, ...]
  --camera-animation  a walkthrough of --camera's glTF animation (LINEAR or STEP), at --fps
  --fps F             frames per second of --camera-animation and --video          [24]
  --video FILE.mp4    also encode a walkthrough's PNGs with ffmpeg (must be on PATH)

other:
  --kernels K         specialised (built with only the features the scene and options use)
                      or generic (everything)                                [specialised]
  --max-depth N       safety cap on path length                                [65536]
)";

constexpr const char* kRenderHelpTail = R"(
The estimator's tuning knobs (--eye-direct, --weights, --beta, --rb-level, --bins, ...):
bundlepath render --help-all
)";

constexpr const char* kRenderHelpTuning = R"(
estimator tuning (the defaults are measured: docs/results.md):
  --eye-direct E      combined with light sampling: the direct light at the first hit, shared
                      with RB, PT's alone (pt), or auto: pt where point, spot and sun lights hold
                      half the light or more, else shared below 96 PT samples per pixel [auto]
  --weights W         combined: product (exact per-vertex weights), paper (the paper's, one
                      density per patch: biased) or none (plain sum: counts twice)  [product]
  --beta B            product weights' per-vertex factor from PT's density P: clamped,
                      min(1, N2/(N1 P)), or balance, N2/(N2 + N1 P) (the paper's)  [clamped]
  --rb-level L        RB's share corrected by PT's estimate of it: per region, then per block
                      down to each pixel, by how far they differ beyond PT's noise, so the
                      image converges to the true one (consistent); per region only (regional)
                      or over the image (corrected): biased by RB's patches; or own  [consistent]
  --rb-light-rate R   combined with light sampling: the probability that a patch traces its
                      shadow ray in an iteration, in (0, 1]      [min(1, pixels / patches)]
  --rb-sun S          combined with light sampling: RB's patches sample a sun when their light
                      sample chooses it (chosen), or each sun every iteration (own)  [chosen]
  --light-selection S lights chosen per patch by a light tree (tree) or by power alone [tree]
  --bins R            ray-bundle buffer of R x R bins          [an average patch covers 4 bins]
  --warmup N          ray-bundle iterations before the image starts                [16]
  --rb-directions D   independent directions, or stratified (experimental: less level noise in
                      short renders, about -1 % bias on long diffuse paths)  [independent]
  --contact-depth F   surfaces closer than F times the scene's diameter along a bundle touch
                      and exchange nothing; 0 turns it off                       [0.001]
  --rb-shading S      RB's eye estimate: gouraud (interpolated across patches) or flat [gouraud]
  --rb-eye-gather G   Lambert pixels gathered once per 16 iterations (blocks, the same image to
                      float rounding) or every iteration (every)                  [blocks]
  --error-batch N     RB iterations per batch of the error estimate (16 to 48 where --ratio
                      auto expects fewer than 4 batches of 64 in --time)            [64]
  --error-levels L    also estimate from batches 2, 4, ... 2^(L-1) times longer, into --stats
                      (the check that the batches outlast RB's correlation)         [1]
)";

}  // namespace

const char* render_help() {
  static const std::string text = std::string(kRenderHelpHead) + kRenderHelpTail;
  return text.c_str();
}

const char* render_help_all() {
  static const std::string text = std::string(kRenderHelpHead) + kRenderHelpTuning;
  return text.c_str();
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
         if (v != "consistent" && v != "regional" && v != "corrected" && v != "own")
           throw UsageError(k + ": expected consistent, regional, corrected or own, got '" + v + "'");
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
      {"--save-every", [&](auto& k, auto& v) { o.save_every = parse_number<double>(k, v, 1e-3, 1e7, "seconds > 0"); }},
      {"--resume", [&](auto&, auto& v) { o.resume_path = v; }},
      {"--time", [&](auto& k, auto& v) { o.seconds = parse_number<double>(k, v, 1e-3, 1e7, "seconds > 0"); }},
      {"--target-error", [&](auto& k, auto& v) {
         o.target_error = parse_number<double>(k, v, 1e-300, 1e300, "a relMSE > 0 (e.g. 0.001)");
       }},
      {"--target-block-error", [&](auto& k, auto& v) {
         o.target_block_error = parse_number<double>(k, v, 1e-300, 1e300, "a relative error > 0 (e.g. 0.02)");
       }},
      {"--regions", [&](auto& k, auto& v) { o.regions = parse_number<int>(k, v, 1, 64, "an integer in 1..64"); }},
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
      {"--patch-clusters", [&](auto& k, auto& v) {
         if (v != "on" && v != "off") throw UsageError(k + ": expected on or off (got '" + v + "')");
         o.patch_clusters = v == "on";
       }},
      {"--patch-refine", [&](auto& k, auto& v) {
         if (v != "on" && v != "off") throw UsageError(k + ": expected on or off (got '" + v + "')");
         o.patch_refine = v == "on";
       }},
      {"--patches", [&](auto& k, auto& v) {
         o.patch_budget = parse_number<std::uint64_t>(k, v, 1, 1ull << 31, "a patch count in 1..2^31");
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
    } else if (arg == "--denoise") {
      o.denoise = true;
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
  if ((o.target_error > 0.0 || o.target_block_error > 0.0) && (spp_given || iterations_given))
    throw UsageError(std::string(o.target_error > 0.0 ? "--target-error" : "--target-block-error") +
                     " ends the render by its error: not with " +
                     (spp_given ? "--spp" : "--iterations") + " (use --time as a cap)");
  const bool unbounded = o.seconds == 0.0 && o.target_error == 0.0 && o.target_block_error == 0.0;
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
