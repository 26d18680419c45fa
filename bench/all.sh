#!/usr/bin/env bash
# Regenerates every bench table and plot: set-up (gnuplot, time), build of the renderer and bench
# tools, references, convergence study, knob studies, the ratio sweep, kernel benchmarks, scaling, and (not with
# --quick) the equal-time, light-sampling and kernel-specialisation comparisons and the ray-bundle
# discretisation, warm-up and bias studies and the check of the error estimate. Writes the CSVs,
# PNGs and Markdown snippets to OUT (bench/results) and OUT/summary.md, which strings the snippets
# together with the machine, the load average and each stage's run time. See bench/README.md.
#
# Usage: bash bench/all.sh [--quick] [--out DIR] [--cap SECONDS] [--repeats N] [--no-setup] [--no-build]
#                          [--no-plots] [--resolutions LIST]
#                          [--stages "references convergence knobs ratio kernels scaling"]
#   --resolutions LIST  image sizes of the convergence study, the ratio sweep and the equal-time
#               comparison on rooms-100000 (WxH, commas) [128x128,640x360,1280x720]
#   --quick     tiny sizes, 1 s budgets, 256-spp references (a few minutes; the CTest smoke test runs
#               it), then checks that every CSV is well formed and every file is there
#   --no-setup  do not run bench/setup.sh (it needs root or sudo)
#   --no-build  use the binaries as they are (the smoke test; the default runs `cmake --build`)
#   --repeats N renders per point in the convergence and knob studies, median relMSE (default 1;
#               each repeat adds about 17 minutes to the full study)
# Environment: see bench/lib.sh (BUNDLEPATH [build/bundlepath], BENCH_CACHE, BENCH_DEVICE, ...).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)

quick=0; out=""; cap=""; repeats=""; setup=1; build=1; plots=1; resolutions=""
stages="references convergence knobs ratio kernels scaling equal_time equal_time_rooms light_sampling kernel_features rb_discretisation rb_warmup rb_bias error_estimate"
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --out) out=$2; shift ;;
    --cap) cap=$2; shift ;;
    --repeats) repeats=$2; shift ;;
    --no-setup) setup=0 ;;
    --no-build) build=0 ;;
    --no-plots) plots=0 ;;
    --stages) stages=$2; shift ;;
    --resolutions) resolutions=$2; shift ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) echo "all.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
if [ $quick -eq 1 ]; then out=${out:-$root/bench-out/quick}; fi
out=${out:-$root/bench/results}
mkdir -p "$out"
out=$(cd "$out" && pwd)

t_all=$(date +%s.%N)
if [ $setup -eq 1 ]; then bash "$here/setup.sh"; fi

export BUNDLEPATH=${BUNDLEPATH:-$root/build/bundlepath}
case $BUNDLEPATH in /*) ;; *) BUNDLEPATH=$PWD/$BUNDLEPATH ;; esac
build_dir=$(dirname "$BUNDLEPATH")
if [ $build -eq 1 ]; then
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
  fi
  cmake --build "$build_dir" -j "$(nproc)" --target bundlepath make_rooms bench_bvh_device bench_bvh_host
fi

common=(--out "$out")
[ $quick -eq 1 ] && common+=(--quick)
study_args=("${common[@]}")
[ -n "$cap" ] && study_args+=(--cap "$cap")
[ -n "$repeats" ] && study_args+=(--repeats "$repeats")
[ $plots -eq 1 ] || study_args+=(--no-plots)
ratio_args=("${common[@]}")
[ -n "$repeats" ] && ratio_args+=(--repeats "$repeats")
[ $plots -eq 1 ] || ratio_args+=(--no-plots)
knobs_args=("${study_args[@]}")  # the knob study stays at one size (cornell-glossy, 128x128)
if [ -n "$resolutions" ]; then
  study_args+=(--resolutions "$resolutions")
  ratio_args+=(--resolutions "$resolutions")
fi

timings=()
stage() {  # name, then the command
  local name=$1; shift
  [[ " $stages " == *" $name "* ]] || return 0
  echo "=== all.sh: $name" >&2
  local t0 t1
  t0=$(date +%s.%N)
  "$@"
  t1=$(date +%s.%N)
  timings+=("$name $(python3 -c "print(f'{$t1 - $t0:.0f}')")")
}
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
stage references bash "$here/convergence.sh" "${study_args[@]}" --references-only
stage convergence bash "$here/convergence.sh" "${study_args[@]}"
stage knobs bash "$here/knobs.sh" "${knobs_args[@]}"
stage ratio bash "$here/ratio.sh" "${ratio_args[@]}"
stage kernels bash "$here/kernels.sh" "${common[@]}"
stage scaling bash "$here/scaling.sh" "${common[@]}"
if [ $quick -eq 0 ]; then  # fixed-budget comparisons: minutes each, so not in the smoke test
  stage equal_time bash -c "bash '$here/equal_time.sh' > '$out/equal-time.md'"
  equal_time_rooms() {  # one table per resolution
    local size
    for size in ${1//,/ }; do
      echo "**rooms-100000 at $size**"; echo
      bash "$here/equal_time.sh" rooms-100000 16 "$size" 8192
      echo
    done > "$out/equal-time-rooms.md"
  }
  stage equal_time_rooms equal_time_rooms "${resolutions:-128x128,640x360,1280x720}"
  stage light_sampling bash -c "bash '$here/light_sampling.sh' > '$out/light-sampling.md'"
  stage kernel_features bash -c "bash '$here/kernel_features.sh' > '$out/kernel-features.md'"
  stage rb_discretisation bash -c "bash '$here/rb_discretisation.sh' > '$out/rb-discretisation.md'"
  stage rb_warmup bash -c "bash '$here/rb_warmup.sh' > '$out/rb-warmup.md'"
  stage rb_bias bash -c "bash '$here/rb_bias.sh' > '$out/rb-bias.md'"
  stage error_estimate bash -c "bash '$here/error_estimate.sh' 128 4 16 0.001 '$out' > /dev/null"
fi
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
total=$(python3 -c "import time; print(f'{time.time() - $t_all:.0f}')")

{
  echo "<!-- generated by bench/all.sh$([ $quick -eq 1 ] && echo ' --quick'); paste into docs/results.md -->"
  echo "Generated by \`bash bench/all.sh$([ $quick -eq 1 ] && echo ' --quick')\` on $(date -u +%Y-%m-%d): $(nproc) cores of"\
       "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $("$BUNDLEPATH" devices 2>/dev/null | head -1)."
  echo "Load average before / after: $load_before / $load_after. Stage times (s):" \
       "$(printf '%s, ' "${timings[@]}" | sed 's/, $//'); total ${total} s."
  echo
  for section in convergence knobs ratio kernels scaling equal-time equal-time-rooms light-sampling kernel-features rb-discretisation rb-warmup rb-bias error-estimate; do
    [ -f "$out/$section.md" ] || continue
    case $section in
      convergence) echo "### Error against time, per scene and mode" ;;
      knobs) echo "### Knobs (cornell-glossy, combined, product weights)" ;;
      ratio) echo "### The ratio c: fixed ratios against --ratio auto" ;;
      kernels) echo "### Kernel throughput" ;;
      scaling) echo "### Scaling" ;;
      equal-time) echo "### Equal time on cornell-glossy (the paper's claim)" ;;
      equal-time-rooms) echo "### Equal time on rooms-100000" ;;
      light-sampling) echo "### Light sampling at equal time on cornell-box" ;;
      kernel-features) echo "### Specialised against generic kernels" ;;
      rb-discretisation) echo "### Ray-bundle discretisation" ;;
      rb-warmup) echo "### Ray-bundle warm-up" ;;
      rb-bias) echo "### Ray-bundle level on the house: bias or noise" ;;
      error-estimate) echo "### Error estimates without a reference" ;;
    esac
    echo
    cat "$out/$section.md"
    echo
  done
} > "$out/summary.md"
echo "all.sh: done in ${total} s; $out/summary.md" >&2

if [ $quick -eq 1 ]; then  # the smoke test: the pipeline works (not the figures)
  fail=0
  for s in convergence knobs ratio scaling; do
    [[ " $stages " == *" $s "* ]] || continue
    python3 "$here/report.py" check "$out/$s.csv" "$s" || fail=1
    [ -s "$out/$s.md" ] || { echo "all.sh: $out/$s.md missing" >&2; fail=1; }
  done
  if [[ " $stages " == *" kernels "* ]]; then
    if ! grep -q "Mrays" "$out/kernels.md" || ! grep -q "warm" "$out/kernels.md"; then
      echo "all.sh: kernels.md incomplete" >&2; fail=1
    fi
  fi
  if [ $plots -eq 1 ]; then
    want=()
    [[ " $stages " == *" convergence "* ]] && want+=(convergence-cornell-box convergence-cornell-glossy convergence-rooms-100000)
    [[ " $stages " == *" knobs "* ]] && want+=(knobs-bins knobs-patch-size knobs-ratio)
    [[ " $stages " == *" ratio "* ]] && want+=(ratio-rooms-lambert-100000-32x18)
    for p in "${want[@]}"; do
      if ! head -c 8 "$out/$p.png" 2>/dev/null | od -An -c | grep -q 'P   N   G'; then
        echo "all.sh: $out/$p.png missing or not a PNG" >&2; fail=1
      fi
    done
  fi
  [ $fail -eq 0 ] && echo "all.sh --quick: pipeline OK" >&2
  exit $fail
fi
