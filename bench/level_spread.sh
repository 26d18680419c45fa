#!/usr/bin/env bash
# The spread of the image level between seeds of short combined renders, for settings that act on
# RB's level noise (issue #12): SEEDS renders per setting at equal work (ITERATIONS RB iterations, the
# combination at --ratio 1/4, so as many PT samples per pixel as iterations / 4), the image mean of
# each against a path-traced reference, its mean and spread between seeds, and the median relMSE.
# Equal work, so the figures do not depend on the machine or its load. Each SETTING is one quoted
# string of render options; the defaults compare --rb-level own and corrected (image/rb_level.h).
# Usage: bench/level_spread.sh [SCENE] [SIZE] [ITERATIONS] [SEEDS] [REFERENCE_SPP] [SETTING...]
#        defaults: rooms-lambert-100000 160x90 144 8 4096 "--rb-level own" "--rb-level corrected"
#        e.g. stratified directions: bench/level_spread.sh rooms-lambert-100000 160x90 144 8 4096 \
#               "--rb-directions independent" "--rb-directions stratified"
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=bench/lib.sh
source "$here/lib.sh"
if [ "${1:-}" = -h ] || [ "${1:-}" = --help ]; then sed -n '2,11p' "$0"; exit 2; fi
cd "$bench_root"
scene=$(bench_scene "${1:-rooms-lambert-100000}")
size=${2:-160x90}
iterations=${3:-144}
seeds=${4:-8}
ref_spp=${5:-4096}
settings=("${@:6}")
[ ${#settings[@]} -gt 0 ] || settings=("--rb-level own" "--rb-level corrected")
mapfile -t wh < <(bench_size_args "$size")
ref=$(bench_reference "$scene" "$ref_spp" "$size")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| setting | image level vs reference, seeds 1–$seeds | mean | spread between seeds (SD) | relMSE (median) |"
echo "|---|---|---|---|---|"
for k in "${!settings[@]}"; do
  read -r -a options <<<"${settings[$k]}"
  for ((seed = 1; seed <= seeds; ++seed)); do
    bench_render "$scene" "${wh[@]}" --mode combined --ratio 1/4 --iterations "$iterations" --seed "$seed" \
      "${options[@]}" --reference "$ref" --out "$tmp/img" --stats "$tmp/$k-$seed.json" 2>/dev/null
  done
  python3 - "${settings[$k]}" "$tmp"/"$k"-*.json <<'PY'
import json, statistics, sys
runs = [json.load(open(p))["reference"]["layers"]["combined"] for p in sys.argv[2:]]
levels = [r["relative_bias"] for r in runs]
print(f"| `{sys.argv[1]}` | {' '.join(f'{100 * x:+.2f}' for x in levels)} % | {100 * statistics.mean(levels):+.2f} % "
      f"| {100 * statistics.stdev(levels):.2f} % | {statistics.median(r['rel_mse'] for r in runs):.3g} |")
PY
done
echo
echo "($(basename "$scene") at $size, $iterations iterations and $((iterations / 4)) spp per render; reference $(basename "$ref"))"
