#!/usr/bin/env bash
# Knob study: error vs wall time for --bins, --patch-size and --ratio on cornell-glossy in
# `--mode combined --weights product`, one knob at a time (the others at the renderer's defaults),
# against the same cached reference as the convergence study. Writes OUT/knobs.csv, OUT/knobs.md
# (relMSE per budget, efficiency relative to the default, the most efficient value) and one log-log
# plot per knob, OUT/knobs-<knob>.png.
#
# Usage: bench/knobs.sh [--quick] [--out DIR] [--cap SECONDS] [--size PIXELS] [--ref-spp N] [--repeats N]
#                       [--no-plots]
#   --repeats N: N renders (independent seeds) per value and budget; the tables use the median relMSE
# Environment: see bench/lib.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"

SCENE=cornell-glossy
BASE_FLAGS="--mode combined --weights product"
# knob | values tried besides the renderer's default (full study) | values for --quick
KNOBS=(
  "--bins|64 96 192 256 384|64"
  "--patch-size|0.1 0.07 0.035 0.025 0.0175|0.1"
  "--ratio|4 1 1/4 1/16 1/64|1"
)

quick=0; repeats=1; out=""; cap=16; size=128; ref_spp=16384; plots=1
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    --out) out=$2; shift ;;
    --cap) cap=$2; shift ;;
    --size) size=$2; shift ;;
    --ref-spp) ref_spp=$2; shift ;;
    --repeats) repeats=$2; shift ;;
    --no-plots) plots=0 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "knobs.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
if [ $quick -eq 1 ]; then
  cap=1; size=32; ref_spp=256
  out=${out:-$bench_root/bench-out/quick}
fi
out=${out:-$bench_root/bench/results}
mkdir -p "$out"
[ $plots -eq 0 ] || bench_require_gnuplot knobs.sh
mapfile -t budgets < <(bench_budgets "$cap")

scene=$(bench_scene "$SCENE")
ref=$(bench_reference "$scene" "$ref_spp" "$size")
csv=$out/knobs.csv
log=$out/knobs.log
: > "$csv"; : > "$log"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# run KNOB VALUE FLAGS...: one render per budget; the default configuration is rendered once per
# budget and its row recorded under every knob.
run() {
  local knob=$1 value=$2; shift 2
  local i b seed rc status rep
  for ((rep = 0; rep < repeats; rep++)); do
  i=0
  for b in "${budgets[@]}"; do
    i=$((i + 1)); seed=$((2000 + 100 * rep + i))
    echo "knobs: $knob $value ${b}s" >&2
    rm -f "$tmp/s.json"
    rc=0
    # shellcheck disable=SC2086
    bench_render "$scene" $BASE_FLAGS "$@" --width "$size" --height "$size" --time "$b" --seed "$seed" \
      --reference "$ref" --out "$tmp/img" --stats "$tmp/s.json" 2>>"$log" || rc=$?
    status=ok; [ $rc -eq 0 ] || status=exit-$rc
    if [ "$value" = default ]; then
      for entry in "${KNOBS[@]}"; do
        python3 "$here/report.py" append "$csv" knobs --stats "$tmp/s.json" --status "$status" knob="${entry%%|*}" \
          value=default flags="$BASE_FLAGS" budget_s="$b" seed="$seed" reference="$(basename "$ref")" reference_spp="$ref_spp"
      done
    else
      python3 "$here/report.py" append "$csv" knobs --stats "$tmp/s.json" --status "$status" knob="$knob" \
        value="$value" flags="$BASE_FLAGS $*" budget_s="$b" seed="$seed" reference="$(basename "$ref")" reference_spp="$ref_spp"
    fi
  done
  done
}

run all default
for entry in "${KNOBS[@]}"; do
  IFS='|' read -r knob full quick_values <<< "$entry"
  values=$full; [ $quick -eq 1 ] && values=$quick_values
  for v in $values; do run "$knob" "$v" "$knob" "$v"; done
done
plot_arg=(); [ $plots -eq 1 ] || plot_arg=(--no-plots)
python3 "$here/report.py" knobs "$csv" "$out" "${plot_arg[@]}"
echo "knobs: wrote $csv and $out/knobs.md" >&2
