#!/usr/bin/env bash
# Convergence study: every scene x every mode at wall-time budgets 1, 2, 4, ... up to --cap seconds,
# relMSE / RMSE / mean bias of each image against a long path-traced reference (bench/reference.sh,
# cached, one per resolution). Writes OUT/convergence.csv, OUT/convergence.md (efficiency table
# relative to PT, per scene and resolution) and one log-log plot per scene and resolution,
# OUT/convergence-<scene>.png for the first resolution listed, OUT/convergence-<scene>-<W>x<H>.png
# for the others.
#
# Usage: bench/convergence.sh [--quick] [--out DIR] [--cap SECONDS] [--resolutions LIST] [--scenes "A B"]
#                             [--modes "LABEL ..."] [--mode-table FILE] [--repeats N] [--no-plots]
#                             [--references-only] [--budgets "S ..."]
#   --budgets "S ..."  these wall-time budgets instead of 1, 2, 4, ... --cap
#   --resolutions LIST image sizes, WxH separated by commas   [128x128,640x360,1280x720]
#                      (--size N is --resolutions NxN); references: the 128x128 spp of SCENES
#                      below there, larger sizes per bench_reference_spp (bench/lib.sh)
#   --quick            32x32, budget 1 s, 256-spp references: checks the pipeline, not the figures
#   --mode-table FILE  extra modes, one "label|renderer flags" per line (added to MODES below)
#   --repeats N        N renders (independent seeds) per mode and budget; the tables and plots use
#                      the median relMSE (one firefly can multiply a single run's relMSE)  [1]
# Environment: see bench/lib.sh (BUNDLEPATH, BENCH_CACHE, BENCH_DEVICE, BENCH_REF_FLAGS);
#   BENCH_EXTRA_MODES="label|flags;label|flags" adds modes too.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"

# The scenes and their references' spp at 128x128 (bench/lib.sh, shared with bench/ratio.sh).
SCENES=("${BENCH_STUDY_SCENES[@]}")
# The modes: label | renderer flags. Add a line to add a mode. A line naming a flag that
# `bundlepath render --help` does not know is skipped with a note (so rows for features that are
# still being written can sit here).
MODES=(
  "pt|--mode pt"
  "pt-no-light-sampling|--mode pt --no-light-sampling"
  "rb|--mode rb"
  "combined-paper|--mode combined --weights paper"
  "combined-product|--mode combined --weights product"
  "combined-product-no-light-sampling|--mode combined --weights product --no-light-sampling"
)

quick=0; repeats=1; out=""; cap=16; resolutions=""; plots=1; refs_only=0; only_scenes=""; only_modes=""; ref_spp_override=""
budgets_override=""
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --out) out=$2; shift ;;
    --cap) cap=$2; shift ;;
    --size) resolutions=${2}x$2; shift ;;
    --resolutions) resolutions=$2; shift ;;
    --scenes) only_scenes=$2; shift ;;
    --modes) only_modes=$2; shift ;;
    --ref-spp) ref_spp_override=$2; shift ;;
    --budgets) budgets_override=$2; shift ;;
    --repeats) repeats=$2; shift ;;
    --mode-table) while IFS= read -r line; do
                    case $line in ''|'#'*) ;; *) MODES+=("$line") ;; esac
                  done < "$2"; shift ;;
    --no-plots) plots=0 ;;
    --references-only) refs_only=1 ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) echo "convergence.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
if [ -n "${BENCH_EXTRA_MODES:-}" ]; then
  IFS=';' read -r -a extra_modes <<< "$BENCH_EXTRA_MODES"
  MODES+=("${extra_modes[@]}")
fi
if [ $quick -eq 1 ]; then
  cap=1; resolutions=${resolutions:-32x32}; ref_spp_override=${ref_spp_override:-256}
  # the Lambert house only when asked for: the smoke test stays short (bench/ratio.sh --quick draws it)
  [ -n "$only_scenes" ] || only_scenes="cornell-box cornell-glossy rooms-100000"
  out=${out:-$bench_root/bench-out/quick}
fi
out=${out:-$bench_root/bench/results}
mkdir -p "$out"
[ $plots -eq 0 ] || bench_require_gnuplot convergence.sh

if [ -n "$budgets_override" ]; then read -r -a budgets <<< "$budgets_override"; else mapfile -t budgets < <(bench_budgets "$cap"); fi
mapfile -t sizes < <(bench_resolutions "${resolutions:-128x128,640x360,1280x720}")
[ ${#sizes[@]} -gt 0 ] || { echo "convergence.sh: no resolution given" >&2; exit 2; }

# Skip modes whose flags this renderer does not have (yet).
usable_modes=()
for entry in "${MODES[@]}"; do
  label=${entry%%|*}; flags=${entry#*|}
  if [ -n "$only_modes" ] && [[ " $only_modes " != *" $label "* ]]; then continue; fi
  missing=""
  for tok in $flags; do
    case $tok in --*) bench_has_flag "$tok" || missing="$missing $tok" ;; esac
  done
  if [ -n "$missing" ]; then
    echo "convergence.sh: skipping mode '$label': the renderer has no$missing" >&2
    continue
  fi
  usable_modes+=("$entry")
done

csv=$out/convergence.csv
log=$out/convergence.log
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[ $refs_only -eq 1 ] || { : > "$csv"; : > "$log"; }

for size in "${sizes[@]}"; do
mapfile -t wh < <(bench_size_args "$size")
for entry in "${SCENES[@]}"; do
  read -r name spp <<< "$entry"
  if [ -n "$only_scenes" ] && [[ " $only_scenes " != *" $name "* ]]; then continue; fi
  spp=${ref_spp_override:-$(bench_reference_spp "$spp" "$size")}
  scene=$(bench_scene "$name")
  ref=$(bench_reference "$scene" "$spp" "$size")
  [ $refs_only -eq 1 ] && { echo "reference $name $size: $ref"; continue; }
  for m in "${usable_modes[@]}"; do
    label=${m%%|*}; flags=${m#*|}
    for ((rep = 0; rep < repeats; rep++)); do
      i=0
      for b in "${budgets[@]}"; do
        i=$((i + 1))
        seed=$((1000 + 100 * rep + i))  # never the reference's seed (7); one stream per budget and repeat
        echo "convergence: $name $size $label ${b}s (seed $seed)" >&2
        rm -f "$tmp/s.json"
        rc=0
        # shellcheck disable=SC2086
        bench_render "$scene" $flags "${wh[@]}" --time "$b" --seed "$seed" \
          --reference "$ref" --out "$tmp/img" --stats "$tmp/s.json" 2>>"$log" || rc=$?
        status=ok; [ $rc -eq 0 ] || status=exit-$rc
        python3 "$here/report.py" append "$csv" convergence --stats "$tmp/s.json" --status "$status" \
          scene="$name" mode="$label" flags="$flags" budget_s="$b" seed="$seed" reference="$(basename "$ref")" \
          reference_spp="$spp"
      done
    done
  done
done
done
[ $refs_only -eq 1 ] && exit 0
plot_arg=(); [ $plots -eq 1 ] || plot_arg=(--no-plots)
python3 "$here/report.py" convergence "$csv" "$out" "${plot_arg[@]}"
echo "convergence: wrote $csv and $out/convergence.md" >&2
