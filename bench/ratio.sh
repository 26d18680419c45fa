#!/usr/bin/env bash
# Ratio sweep: `--mode combined` (product weights) at fixed ratios c = 64, 16, 4, 1, 1/4, 1/16, 1/64, 1/256 and at
# `--ratio auto`, on every bench scene and resolution, at wall-time budgets, against the cached PT
# references of the convergence study. Efficiency 1/(relMSE·t) per setting (t = render_seconds, plus
# the probe's own seconds for auto: its work is thrown away, so auto pays for it); the table checks
# issue #12's requirement that auto lands within 1.25x of the best fixed ratio's efficiency on every
# scene and resolution. Writes OUT/ratio.csv, OUT/ratio.md (also printed) and one log-log plot per
# scene and resolution, OUT/ratio-<scene>-<W>x<H>.png.
#
# Usage: bench/ratio.sh [--quick] [--out DIR] [--budgets "4 16"] [--resolutions LIST] [--scenes "A B"]
#                       [--ratios "64 16 4 1 1/4 1/16 1/64 1/256 auto"] [--repeats N] [--no-plots]
#   --resolutions LIST WxH separated by commas  [128x128,640x360,1280x720]
#   --budgets          wall-time budgets in seconds; the efficiency of a setting is the geometric
#                      mean over them of 1/(relMSE·t)  [4 16]
#   --repeats N        N renders (independent seeds) per point, median relMSE  [1]
#   --quick            rooms-lambert-100000 at 32x18, 1 s, ratios 1/16 and auto, 256-spp reference:
#                      checks the pipeline, not the figures
# Environment: see bench/lib.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"

# The scenes of bench/convergence.sh (bench/lib.sh), so both studies share the cached references.
SCENES=("${BENCH_STUDY_SCENES[@]}")
BASE_FLAGS="--mode combined --weights product"

quick=0; repeats=1; out=""; budgets="4 16"; resolutions="128x128,640x360,1280x720"; plots=1
only_scenes=""; ratios="64 16 4 1 1/4 1/16 1/64 1/256 auto"; ref_spp_override=""
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --out) out=$2; shift ;;
    --budgets) budgets=$2; shift ;;
    --resolutions) resolutions=$2; shift ;;
    --scenes) only_scenes=$2; shift ;;
    --ratios) ratios=$2; shift ;;
    --ref-spp) ref_spp_override=$2; shift ;;
    --repeats) repeats=$2; shift ;;
    --no-plots) plots=0 ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "ratio.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
if [ $quick -eq 1 ]; then
  budgets=1; resolutions=32x18; ratios="1/16 auto"; ref_spp_override=${ref_spp_override:-256}
  only_scenes=${only_scenes:-rooms-lambert-100000}
  out=${out:-$bench_root/bench-out/quick}
fi
out=${out:-$bench_root/bench/results}
mkdir -p "$out"
[ $plots -eq 0 ] || bench_require_gnuplot ratio.sh
mapfile -t sizes < <(bench_resolutions "$resolutions")

csv=$out/ratio.csv
log=$out/ratio.log
: > "$csv"; : > "$log"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

for size in "${sizes[@]}"; do
  mapfile -t wh < <(bench_size_args "$size")
  for entry in "${SCENES[@]}"; do
    read -r name spp <<< "$entry"
    if [ -n "$only_scenes" ] && [[ " $only_scenes " != *" $name "* ]]; then continue; fi
    spp=${ref_spp_override:-$(bench_reference_spp "$spp" "$size")}
    scene=$(bench_scene "$name")
    ref=$(bench_reference "$scene" "$spp" "$size")
    # Untimed (not in --quick): the first launch of each kernel builds its work-group code (PoCL),
    # which would land in the first setting's time.
    [ $quick -eq 1 ] || bench_render "$scene" $BASE_FLAGS --ratio 1 --spp 1 "${wh[@]}" --out "$tmp/warm" 2>>"$log" >/dev/null || true
    for ratio in $ratios; do
      for ((rep = 0; rep < repeats; rep++)); do
        i=0
        for b in $budgets; do
          i=$((i + 1)); seed=$((3000 + 100 * rep + i))
          echo "ratio: $name $size --ratio $ratio ${b}s (seed $seed)" >&2
          rm -f "$tmp/s.json"
          rc=0
          # shellcheck disable=SC2086
          bench_render "$scene" $BASE_FLAGS --ratio "$ratio" "${wh[@]}" --time "$b" --seed "$seed" \
            --reference "$ref" --out "$tmp/img" --stats "$tmp/s.json" 2>>"$log" || rc=$?
          status=ok; [ $rc -eq 0 ] || status=exit-$rc
          python3 "$here/report.py" append "$csv" ratio --stats "$tmp/s.json" --status "$status" scene="$name" \
            setting="$ratio" flags="$BASE_FLAGS --ratio $ratio" budget_s="$b" seed="$seed" \
            reference="$(basename "$ref")" reference_spp="$spp"
        done
      done
    done
  done
done
plot_arg=(); [ $plots -eq 1 ] || plot_arg=(--no-plots)
python3 "$here/report.py" ratio "$csv" "$out" "${plot_arg[@]}"
cat "$out/ratio.md"
echo "ratio: wrote $csv and $out/ratio.md" >&2
