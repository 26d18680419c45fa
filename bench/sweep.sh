#!/usr/bin/env bash
# Issue #12's sweep: for every bench scene at every resolution, the convergence study of --mode pt,
# --mode rb and --mode combined at its defaults (budgets 1, 2, ... CAP s) and the ratio sweep
# (fixed ratios and auto at CAP s), then the default-mode check (bench/report.py modes): is the
# combination at its defaults at least as good as the better estimator, and is --ratio auto within
# 1.25x of the best fixed ratio? One folder per resolution, OUT/res-<W>x<H>/{conv,ratio}/, and
# OUT/modes.md.
# Usage: bench/sweep.sh [--out DIR] [--cap SECONDS] [--resolutions LIST] [--scenes "A B"] [--budget-only]
#        defaults: bench/results, 16, 128x128,640x360,1280x720, every scene of BENCH_STUDY_SCENES
#        --budget-only: both studies at CAP seconds alone (no convergence curve; the check needs only
#        that budget, at about a third of the time)
# About 4 minutes per scene and resolution at the default cap, once the references are cached
# (bench/convergence.sh --references-only renders them).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
out=$bench_root/bench/results; cap=16; resolutions=128x128,640x360,1280x720; scenes=""; budget_only=0
while [ $# -gt 0 ]; do
  case $1 in
    --out) out=$2; shift ;;
    --cap) cap=$2; shift ;;
    --resolutions) resolutions=$2; shift ;;
    --scenes) scenes=$2; shift ;;
    --budget-only) budget_only=1 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "sweep.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
scene_args=(); [ -z "$scenes" ] || scene_args=(--scenes "$scenes")
conv_budgets=()
[ $budget_only -eq 0 ] || conv_budgets=(--budgets "$cap" --no-plots)
dirs=()
for size in ${resolutions//,/ }; do
  dir=$out/res-$size
  bash "$here/convergence.sh" --resolutions "$size" "${scene_args[@]}" --modes "pt rb combined-product" \
    --cap "$cap" "${conv_budgets[@]}" --out "$dir/conv"
  bash "$here/ratio.sh" --resolutions "$size" "${scene_args[@]}" --budgets "$cap" --out "$dir/ratio"
  dirs+=("$dir/conv" "$dir/ratio")
done
python3 "$here/report.py" modes "$out" "${dirs[@]}"
